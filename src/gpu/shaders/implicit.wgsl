// Pass implicit_solve (physics/implicit.rs `implicit_euler_block`): backward Euler by Newton
// on the incremental potential, one invocation per strand, the strand's banded system in
// private memory (f32 here; the CPU solves in f64). `hair_forces` has left the explicit forces
// (adhesion, cohesion) and the new wetness in state_out, which this pass then overwrites; drag
// is implicit here, in the inertial term. The solve starts from `start_of` (prepended: the state
// as it is, or BDF2's blend with the last substep's, physics/bdf2.rs) and takes the substep's
// solve step `S.blend.z` (1 / it in `S.blend.w`).
// Prepended constants: P_MAX (longest strand), ITERATIONS, HAS_FORCES, COLLIDE.

// Group 1 is the water's (bound only by hair_forces); the strand table (and BDF2's history)
// sits in group 2.
@group(2) @binding(0) var<storage, read> strand_first: array<u32>;

const N_MAX: u32 = 3u * P_MAX;

var<private> band: array<array<f32, BAND + 1u>, N_MAX>;
var<private> rhs: array<f32, N_MAX>;
var<private> tgt: array<f32, N_MAX>;
var<private> xi: array<f32, N_MAX>;
var<private> trial: array<f32, N_MAX>;
var<private> grad: array<f32, N_MAX>;
// The solve's start positions (BDF2: the blend).
var<private> x0: array<f32, N_MAX>;

fn dof3(x: ptr<private, array<f32, N_MAX>>, i: u32) -> vec3<f32> {
    return vec3<f32>((*x)[3u * i], (*x)[3u * i + 1u], (*x)[3u * i + 2u]);
}

// One spring's share of the energy (times h^2), of the gradient and, with `hess`, of the band.
fn spring_terms(x: ptr<private, array<f32, N_MAX>>, base: u32, a: u32, b: u32, k: f32, c: f32, rest: f32,
                hess: bool) -> f32 {
    let d = dof3(x, b) - dof3(x, a);
    let len = sqrt(dot(d, d));
    let ok = len > MIN_LENGTH;
    let inv = select(0.0, 1.0 / len, ok);
    let n = d * inv;
    // Damping potential about the spring's vector at the start of the step.
    let d0 = dof3(&x0, b) - dof3(&x0, a);
    let len0 = sqrt(dot(d0, d0));
    let n0 = select(vec3<f32>(0.0), d0 / len0, len0 > MIN_LENGTH);
    let dd = d - d0;
    let ch = S.blend.z * c;
    let hh = S.blend.z * S.blend.z;
    let stretch = select(0.0, len - rest, ok);
    var pdd = dd;
    var damp_e = dot(dd, dd);
    if (AXIAL) {
        let t = dot(n0, dd);
        pdd = n0 * t;
        damp_e = t * t;
    }
    for (var r = 0u; r < 3u; r++) {
        let gr = hh * k * stretch * n[r] + ch * pdd[r];
        grad[3u * b + r] += gr;
        grad[3u * a + r] -= gr;
    }
    if (hess) {
        let alpha = select(0.0, max(1.0 - rest * inv, 0.0), ok);
        let off = 3u * (b - a);
        for (var r = 0u; r < 3u; r++) {
            for (var q = 0u; q < 3u; q++) {
                var damp = select(0.0, 1.0, r == q);
                if (AXIAL) {
                    damp = n0[r] * n0[q];
                }
                let v = hh * k * (alpha * select(0.0, 1.0, r == q) + (1.0 - alpha) * n[r] * n[q]) + ch * damp;
                if (q <= r) {
                    band[3u * a + r][r - q] += v;
                    band[3u * b + r][r - q] += v;
                }
                band[3u * b + r][off + r - q] -= v;
            }
        }
    }
    return hh * 0.5 * k * stretch * stretch + 0.5 * ch * damp_e;
}

// Energy (times h^2) and gradient of the strand at `x`; the band too with `hess`.
fn strand_terms(x: ptr<private, array<f32, N_MAX>>, base: u32, p: u32, hess: bool) -> f32 {
    var e = 0.0;
    for (var i = 0u; i < p; i++) {
        let w = points[base + i].inv_mass;
        let m = inertia(base + i, w);
        for (var c = 0u; c < 3u; c++) {
            let r = 3u * i + c;
            let d = (*x)[r] - tgt[r];
            e += 0.5 * m * d * d;
            grad[r] = m * d;
            if (hess) {
                band[r] = array<f32, BAND + 1u>(select(1.0, m, w > 0.0), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
            }
        }
    }
    for (var i = 0u; i + 1u < p; i++) {
        let ps = points[base + i];
        e += spring_terms(x, base, i, i + 1u, ps.stretch_k, ps.stretch_c, ps.rest_stretch, hess);
    }
    if (BEND) {
        for (var i = 0u; i + 2u < p; i++) {
            let pb = points[base + i];
            e += spring_terms(x, base, i, i + 2u, pb.bend_k, pb.bend_c, pb.rest_bend, hess);
        }
    }
    return e;
}

// Cholesky of the band (L overwrites it), then forward and back substitution of rhs.
fn solve_banded(n: u32) {
    for (var r = 0u; r < n; r++) {
        for (var k = min(BAND, r); k >= 1u; k--) {
            let c = r - k;
            var s = band[r][k];
            for (var j = k + 1u; j <= min(BAND, r); j++) {
                s -= band[r][j] * band[c][j - k];
            }
            band[r][k] = s / band[c][0];
        }
        var s = band[r][0];
        for (var k = 1u; k <= min(BAND, r); k++) {
            s -= band[r][k] * band[r][k];
        }
        band[r][0] = sqrt(max(s, PIVOT_FLOOR_F32));
    }
    for (var r = 0u; r < n; r++) {
        var s = rhs[r];
        for (var k = 1u; k <= min(BAND, r); k++) {
            s -= band[r][k] * rhs[r - k];
        }
        rhs[r] = s / band[r][0];
    }
    for (var rr = n; rr > 0u; rr--) {
        let r = rr - 1u;
        var s = rhs[r];
        for (var k = 1u; k <= min(BAND, n - 1u - r); k++) {
            s -= band[r + k][k] * rhs[r + k];
        }
        rhs[r] = s / band[r][0];
    }
}

@compute @workgroup_size(WG)
fn implicit_solve(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let s = linear_id(wid, nwg, lid);
    if (s >= P.strands) {
        return;
    }
    let base = strand_first[s];
    let p = strand_first[s + 1u] - base;
    let n = 3u * p;
    // Inertial target, and the start iterate x + h v (pinned points on the head's target).
    for (var i = 0u; i < p; i++) {
        let st = start_of(base + i, state_in[base + i]);
        for (var c = 0u; c < 3u; c++) {
            x0[3u * i + c] = st.x[c];
        }
        let pt = points[base + i];
        var f = vec3<f32>(0.0);
        if (HAS_FORCES) {
            f = state_out[base + i].x.xyz;
        }
        let t = tgt_of(base + i, pt, st, f);
        for (var c = 0u; c < 3u; c++) {
            tgt[3u * i + c] = t[c];
        }
        var x = st.x.xyz + S.blend.z * st.v.xyz;
        if (pt.inv_mass == 0.0) {
            x = pinned_target(pt);
        }
        for (var c = 0u; c < 3u; c++) {
            xi[3u * i + c] = x[c];
        }
    }
    for (var it = 0u; it < ITERATIONS; it++) {
        let e0 = strand_terms(&xi, base, p, true);
        // Pinned DOFs do not move: identity rows and columns, zero gradient.
        for (var i = 0u; i < p; i++) {
            if (points[base + i].inv_mass > 0.0) {
                continue;
            }
            for (var c = 0u; c < 3u; c++) {
                let col = 3u * i + c;
                for (var k = 1u; k <= BAND; k++) {
                    if (col + k < n) {
                        band[col + k][k] = 0.0;
                    }
                    if (k <= col) {
                        band[col][k] = 0.0;
                    }
                }
                band[col][0] = 1.0;
                grad[col] = 0.0;
            }
        }
        for (var r = 0u; r < n; r++) {
            rhs[r] = -grad[r];
        }
        solve_banded(n);
        var slope = 0.0;
        for (var r = 0u; r < n; r++) {
            slope += grad[r] * rhs[r];
        }
        // Backtracking line search (Armijo, at most 12 halvings; f32 energies compare within
        // their own rounding).
        var step = 1.0;
        var done = false;
        for (var tries = 0; tries < 12; tries++) {
            for (var r = 0u; r < n; r++) {
                trial[r] = xi[r] + step * rhs[r];
            }
            let e = strand_terms(&trial, base, p, false);
            if (e <= e0 + ARMIJO_C1 * step * slope + ARMIJO_SLACK_F32 * abs(e0)) {
                done = true;
                break;
            }
            step *= 0.5;
        }
        if (done) {
            for (var r = 0u; r < n; r++) {
                xi[r] += step * rhs[r];
            }
        }
    }
    for (var i = 0u; i < p; i++) {
        let idx = base + i;
        let st = state_in[idx];
        var x = dof3(&xi, i);
        var v = (x - dof3(&x0, i)) * S.blend.w;
        var wet = st.x.w;
        if (HAS_FORCES) {
            wet = state_out[idx].x.w;
        }
        if (COLLIDE && points[idx].inv_mass > 0.0) {
            for (var c = 0u; c < N_COLLIDERS; c++) {
                collide(&x, &v, S.colliders[c], P.friction);
            }
        }
        check(idx, x, v);
        state_out[idx] = State(vec4<f32>(x, wet), vec4<f32>(v, 0.0));
    }
}

// The inertial term's mass of point i under implicit drag, m + h c (0 pinned).
fn inertia(i: u32, w: f32) -> f32 {
    return select(0.0, 1.0 / w + S.blend.z * drag_at(i), w > 0.0);
}

// x~ = x + h v + h^2 (f / m + g) for a free point, weighted toward x + h wind by the drag's
// share h c / (m + h c) (pinned points: unused).
fn tgt_of(idx: u32, pt: Point, st: State, f: vec3<f32>) -> vec3<f32> {
    let h = S.blend.z;
    let inertial = st.x.xyz + h * st.v.xyz + h * h * (f * pt.inv_mass + P.g.xyz);
    let m = select(0.0, 1.0 / pt.inv_mass, pt.inv_mass > 0.0);
    // A pinned point (m = 0) takes no share; the guard is a select, not a floor under the
    // divisor: 1e-38 is below f32's smallest normal, a GPU that flushes denormals (the H100
    // does) read it as 0, and 0 / 0 made every pinned target NaN, the strand's energy NaN,
    // and the line search refuse every Newton step: hair froze under implicit Euler and BDF2
    // wherever the drag was 0.
    let mw = select(0.0, m / (m + h * drag_at(idx)), m > 0.0);
    return mw * inertial + (1.0 - mw) * (st.x.xyz + h * P.wind.xyz);
}
