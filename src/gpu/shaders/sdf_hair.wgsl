// Pass collide, SDF part, for hair (cpu/kernel.rs: after the analytic colliders, in the same
// pass): every free point of the state the hair kernel just wrote.

@group(0) @binding(3) var<storage, read> points: array<Point>;
@group(0) @binding(4) var<storage, read_write> state: array<State>;

@compute @workgroup_size(WG)
fn hair_sdf(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
            @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || points[i].inv_mass <= 0.0) {
        return;
    }
    let st = state[i];
    var x = st.x.xyz;
    var v = st.v.xyz;
    for (var k = 0u; k < NSDF; k++) {
        collide_sdf(&x, &v, SS.sdfs[k], P.friction);
    }
    state[i] = State(vec4<f32>(x, st.x.w), vec4<f32>(v, st.v.w));
}
