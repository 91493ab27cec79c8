// Pass cohesion (cpu/bridges.rs `gather`; docs/WET_MODEL.md §5), in the hair module: each wet
// point's pull toward its bridged neighbours at the substep's start (BDF2: at x + h v,
// `explicit_point`), parked in state_out's velocity with w = 1, which the hair kernel (or
// hair_forces) adds in the CPU's place and then overwrites with w = 0. Points with no bridge
// are not written: every writer of a state leaves w = 0 in its velocity, so their parked w
// reads 0 and the kernel adds nothing (a write per point cost more than the pulls under light
// rain).

@group(3) @binding(0) var<storage, read> bridge: array<u32>;

// wet::bridge_scale: c (1 - r / d_b) below the bridge length, else 0.
fn bridge_scale(c: f32, r: f32) -> f32 {
    if (r < P.bridge_length) {
        return c * (1.0 - r / P.bridge_length);
    }
    return 0.0;
}

@compute @workgroup_size(WG)
fn cohesion(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
            @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    let at = i * BR_WORDS;
    let mask = bridge[P.bridge_masks + i];
    if (mask == 0u) {
        // Most points, under light rain: no read of the state, no write.
        return;
    }
    let xi = explicit_point(state_in[i]);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < MAX_BRIDGES; k++) {
        if ((mask & (1u << k)) != 0u) {
            let d = explicit_point(state_in[bridge[at + BR_NEAREST + k]]) - xi;
            sum += d * bridge_scale(bitcast<f32>(bridge[at + BR_COEF + k]), length(d));
        }
    }
    state_out[i].v = vec4<f32>(sum, 1.0);
}
