// Pass volume, response (cpu/volume.rs, `sample` and `respond`): every free point reads the
// density's excess over the rest density and its gradient, and the hair's velocity, from the
// eight samples around it; its velocity relaxes toward the hair's and, where the excess is
// positive, is pushed down the gradient by the pressure, scaled by 1 - wetness.

@group(0) @binding(3) var<storage, read_write> volume_grid: array<u32>;

fn volume_word(c: u32, w: u32) -> f32 {
    let at = c * VOLUME_WORDS + w;
    return volume_value(vec2<u32>(volume_grid[at], volume_grid[at + 1u]));
}

@compute @workgroup_size(WG)
fn volume_respond(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    var f = vec3<f32>(0.0);
    let at = volume_point(i, &f);
    if (at.y == 0u) {
        return;
    }
    let st = state[i];
    var rho: array<f32, 8>;
    var m = 0.0;
    var pm = vec3<f32>(0.0);
    for (var k = 0u; k < 8u; k++) {
        let c = volume_corner(at.x, k);
        let mc = volume_word(c, 0u);
        rho[k] = max(mc * VU.law.w - VU.law.z, 0.0);
        let w = volume_weight(f, k);
        m += w * mc;
        pm += w * vec3<f32>(volume_word(c, 2u), volume_word(c, 4u), volume_word(c, 6u));
    }
    let r = trilinear(rho, f);
    let density = r.x;
    let gradient = r.yzw / VU.origin.w;
    var u = vec3<f32>(0.0);
    if (m > 0.0) {
        u = pm * (1.0 / m);
    }
    var v = st.v.xyz + (u - st.v.xyz) * VU.law.x;
    if (density > 0.0) {
        let g = vec3<f32>(dot(VU.wx.xyz, gradient), dot(VU.wy.xyz, gradient), dot(VU.wz.xyz, gradient));
        v = v - g * (VU.law.y * (1.0 - clamp(st.x.w, 0.0, 1.0)));
    }
    state[i] = State(st.x, vec4<f32>(v, st.v.w));
}
