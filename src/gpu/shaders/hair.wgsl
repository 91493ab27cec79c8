// The hair substep: one invocation per hair point, the CPU block kernel's passes in the same
// order (cpu/step.rs `block_substep_impl`): drag, stretch_springs, bend_springs, adhesion,
// integrate, collide. Each point gathers the springs it belongs to, so no two invocations
// write the same point; state_in / state_out ping-pong between substeps.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<uniform> S: Substep;
@group(0) @binding(2) var<storage, read> points: array<Point>;
@group(0) @binding(3) var<storage, read> state_in: array<State>;
@group(0) @binding(4) var<storage, read_write> state_out: array<State>;
// [STATUS_SPEED2] largest v^2 this step (f32 bits), [STATUS_FLAGS] failure flags,
// [STATUS_FAILED_POINT] first non-finite point (min), [3] unused.
@group(0) @binding(5) var<storage, read_write> status: array<atomic<u32>, 4>;

// Eq. 1 (physics/spring.rs `spring`): the force on point a from the spring a-b; b gets minus it.
fn spring(xa: vec3<f32>, xb: vec3<f32>, va: vec3<f32>, vb: vec3<f32>, rest: f32, k: f32, c: f32) -> vec3<f32> {
    let d = xb - xa;
    let len = sqrt(dot(d, d));
    var inv = 0.0;
    if (len > MIN_LENGTH) {
        inv = 1.0 / len;
    }
    let n = d * inv;
    let dv = vb - va;
    if (AXIAL) {
        let m = k * (len - rest) + c * dot(dv, n);
        return m * n;
    }
    let m = k * (len - rest);
    return m * n + c * dv;
}

// physics/per_length.rs `PerLength::at`: point i's air drag coefficient, N·s/m: P.drag on every
// point, or in proportion to the hair it stands for.
fn drag_at(i: u32) -> f32 {
    if (P.drag_scale > 0.0) {
        return rest_around(i) * P.drag_scale;
    }
    return P.drag;
}

// Pass drag: linear air drag toward the wind (it starts the force sum, as on the CPU).
fn drag(i: u32, v: vec3<f32>, f: ptr<function, vec3<f32>>) {
    *f = drag_at(i) * (P.wind.xyz - v);
}

// Pass stretch_springs: the springs (i-1, i) and (i, i+1) this point belongs to, added in the
// CPU's order so that the sums round alike.
fn stretch_springs(i: u32, pt: Point, x: vec3<f32>, v: vec3<f32>, f: ptr<function, vec3<f32>>) {
    if (i > pt.first) {
        let a = state_in[i - 1u];
        *f -= spring(a.x.xyz, x, a.v.xyz, v, points[i - 1u].rest_stretch, points[i - 1u].stretch_k, points[i - 1u].stretch_c);
    }
    if (i < pt.last) {
        let b = state_in[i + 1u];
        *f += spring(x, b.x.xyz, v, b.v.xyz, pt.rest_stretch, pt.stretch_k, pt.stretch_c);
    }
}

// Pass bend_springs: the springs (i-2, i) and (i, i+2).
fn bend_springs(i: u32, pt: Point, x: vec3<f32>, v: vec3<f32>, f: ptr<function, vec3<f32>>) {
    if (i >= pt.first + 2u) {
        let a = state_in[i - 2u];
        *f -= spring(a.x.xyz, x, a.v.xyz, v, points[i - 2u].rest_bend, points[i - 2u].bend_k, points[i - 2u].bend_c);
    }
    if (i + 2u <= pt.last) {
        let b = state_in[i + 2u];
        *f += spring(x, b.x.xyz, v, b.v.xyz, pt.rest_bend, pt.bend_k, pt.bend_c);
    }
}

// Where a pinned point goes this substep: its rest position under the head transform, or,
// with skinned roots, the target pass pin_roots wrote over its rest position (roots.wgsl).
fn pinned_target(pt: Point) -> vec3<f32> {
    if (ROOTS) {
        return pt.rest;
    }
    return (S.head * vec4<f32>(pt.rest, 1.0)).xyz;
}

// Pass integrate (physics/integrate.rs `symplectic_euler_row`): free points take
// v += h (f/m + g), x += h v; pinned points move to their target with the velocity that
// reaches it.
fn integrate(pt: Point, x: ptr<function, vec3<f32>>, v: ptr<function, vec3<f32>>, f: vec3<f32>) {
    let w = pt.inv_mass;
    if (w == 0.0) {
        let t = pinned_target(pt);
        *v = (t - *x) * P.inv_h;
        *x = t;
        return;
    }
    *v = *v + P.h * (f * w + P.g.xyz);
    *x = *x + P.h * *v;
}

// Records speed and non-finite values for the step's report.
fn check(i: u32, x: vec3<f32>, v: vec3<f32>) {
    let v2 = dot(v, v);
    if (non_finite(v2 + x.x + x.y + x.z)) {
        atomicOr(&status[STATUS_FLAGS], FLAG_HAIR_NONFINITE);
        atomicMin(&status[STATUS_FAILED_POINT], i);
        return;
    }
    atomicMax(&status[STATUS_SPEED2], bitcast<u32>(v2));
}
