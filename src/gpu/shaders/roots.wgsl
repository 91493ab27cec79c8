// Roots on a skinned mesh (physics/roots.rs). Pass pin_roots, before each substep's hair
// kernel, writes each pinned point's target for the substep (`RootFrame::place` of the frame
// `root_between` gives) over its record's rest position, which the hair kernels read as the
// target when ROOTS is on. Pass carry_roots carries whole strands rigidly from one frame to
// another (`RootFrame::carry`), at rest: a teleport, or a reset onto the frames.

@group(0) @binding(0) var<uniform> RU: RootsUniform;
@group(0) @binding(1) var<storage, read> root_pairs: array<RootPair>;
@group(0) @binding(2) var<storage, read> pins: array<Pin>;
@group(0) @binding(3) var<storage, read_write> points: array<Point>;
@group(0) @binding(4) var<storage, read> carries: array<Carry>;
@group(0) @binding(5) var<storage, read_write> state: array<State>;

// p q (Hamilton product, x y z w).
fn quat_mul(p: vec4<f32>, q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        p.w * q.xyz + q.w * p.xyz + cross(p.xyz, q.xyz),
        p.w * q.w - dot(p.xyz, q.xyz),
    );
}

// `slerp`: along the shorter arc; near-equal rotations by a normalized lerp.
fn slerp(p: vec4<f32>, q0: vec4<f32>, a: f32) -> vec4<f32> {
    var d = dot(p, q0);
    var q = q0;
    if (d < 0.0) {
        d = -d;
        q = -q;
    }
    if (d > 0.9995) {
        return normalize(p * (1.0 - a) + q * a);
    }
    let theta = acos(d);
    let s = sin(theta);
    let wp = sin((1.0 - a) * theta) / s;
    let wq = sin(a * theta) / s;
    return normalize(p * wp + q * wq);
}

@compute @workgroup_size(WG)
fn pin_roots(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
             @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= arrayLength(&pins)) {
        return;
    }
    let pin = pins[k];
    let r = root_pairs[pin.at.y];
    // `root_between`: the ends exact.
    var pos = r.to_pos.xyz;
    var rot = r.to_rot;
    if (RU.a <= 0.0) {
        pos = r.from_pos.xyz;
        rot = r.from_rot;
    } else if (RU.a < 1.0) {
        pos = r.from_pos.xyz + (r.to_pos.xyz - r.from_pos.xyz) * RU.a;
        rot = slerp(r.from_rot, r.to_rot, RU.a);
    }
    points[pin.at.x].rest = pos + quat_rotate(rot, pin.offset.xyz);
}

@compute @workgroup_size(WG)
fn carry_roots(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
               @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= RU.count) {
        return;
    }
    let c = carries[k];
    let turn = quat_mul(c.to_rot, vec4<f32>(-c.from_rot.xyz, c.from_rot.w));
    for (var i = c.span.x; i <= c.span.y; i++) {
        let st = state[i];
        let x = c.to_pos.xyz + quat_rotate(turn, st.x.xyz - c.from_pos.xyz);
        state[i] = State(vec4<f32>(x, st.x.w), vec4<f32>(0.0, 0.0, 0.0, st.v.w));
    }
}
