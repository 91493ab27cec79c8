// Pass volume, spreading (cpu/volume.rs): every free point adds its dry mass and its momentum
// to the eight samples around it by integer atomics (`spread_mass`, `spread`, `share`).

@group(0) @binding(3) var<storage, read_write> volume_grid: array<atomic<u32>>;

fn volume_add(at: u32, v: vec2<u32>) {
    let old = atomicAdd(&volume_grid[at], v.x);
    atomicAdd(&volume_grid[at + 1u], v.y + select(0u, 1u, old + v.x < old));
}

@compute @workgroup_size(WG)
fn volume_spread(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                 @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    var f = vec3<f32>(0.0);
    let at = volume_point(i, &f);
    if (at.y == 0u) {
        return;
    }
    let st = state[i];
    let mass = spread_mass(1.0 / points[i].inv_mass, st.x.w);
    let v = clamp(st.v.xyz, vec3<f32>(-MAX_SPREAD_SPEED), vec3<f32>(MAX_SPREAD_SPEED));
    for (var k = 0u; k < 8u; k++) {
        let m = mass * volume_weight(f, k);
        let c = volume_corner(at.x, k) * VOLUME_WORDS;
        volume_add(c, volume_quanta(m));
        volume_add(c + 2u, volume_quanta(m * v.x));
        volume_add(c + 4u, volume_quanta(m * v.y));
        volume_add(c + 6u, volume_quanta(m * v.z));
    }
}
