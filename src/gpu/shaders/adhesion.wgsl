// Eq. 2 on the GPU (physics/adhesion.rs): each hair point gathers the particles of the grid
// cells within r_max; the opposite force goes to the particle with a float atomic add, so
// hair and water exchange exactly equal and opposite forces (up to summation order).

@group(1) @binding(0) var<storage, read_write> sorted: array<Particle>;
@group(1) @binding(1) var<storage, read_write> water_force: array<atomic<u32>>;
@group(1) @binding(2) var<storage, read> grid: array<u32>;
// Absorption's per-particle scratch (buffers::absorb_words; a placeholder without absorption).
@group(1) @binding(3) var<storage, read_write> absorb_scratch: array<atomic<u32>>;

// Eq. 2's factor (physics/adhesion.rs `force_scale`): s g(d) / d within [MIN_DISTANCE, r_max],
// else 0, for a particle of strength s.
fn force_scale(d2: f32, s: f32) -> f32 {
    if (d2 > P.r_max * P.r_max || d2 < MIN_DISTANCE * MIN_DISTANCE) {
        return 0.0;
    }
    let d = sqrt(d2);
    let u = (2.0 * d - P.r_min - P.r_max) / (P.r_min - P.r_max);
    return s * (1.0 - u * u) / d;
}

fn atomic_add_f32(i: u32, v: f32) {
    var old = atomicLoad(&water_force[i]);
    loop {
        let r = atomicCompareExchangeWeak(&water_force[i], old, bitcast<u32>(bitcast<f32>(old) + v));
        if (r.exchanged) {
            break;
        }
        old = r.old_value;
    }
}

// Absorption's ask (physics/absorb.rs `WetRow::demand`): the demand joins the particle's sum
// (64-bit, by integer atomics: the same in any order) and its largest.
fn ask(k: u32, demand: u32) {
    let at = k * ABS_WORDS;
    let old = atomicAdd(&absorb_scratch[at + ABS_TOTAL], demand);
    if (old + demand < old) {
        atomicAdd(&absorb_scratch[at + ABS_TOTAL + 1u], 1u);
    }
    atomicMax(&absorb_scratch[at + ABS_BEST], demand);
}

// Pass adhesion: returns the force on the hair point at x and sets `near` when a particle is
// within r_max (for wetting). With absorption, a particle pulls with the water it still holds
// and the point (at saturation `sat`) asks it for water.
fn adhesion(x: vec3<f32>, sat: f32, near: ptr<function, f32>) -> vec3<f32> {
    var acc = vec3<f32>(0.0);
    let r = P.r_max;
    var span: Span;
    if (!near_span(x, r, &span)) {
        return acc;
    }
    for (var cx = span.c0.x; cx <= span.c1.x; cx++) {
        for (var cy = span.c0.y; cy <= span.c1.y; cy++) {
            let run = span_row(span, cx, cy);
            for (var k = run.x; k < run.y; k++) {
                let d = sorted[k].x.xyz - x;
                let d2 = dot(d, d);
                if (d2 > r * r) {
                    continue;
                }
                *near = 1.0;
                var s = P.adhesion;
                if (P.absorbs != 0u) {
                    let q = sorted[k].mass;
                    s = f32(q) * P.strength_per_quantum;
                    let demand = absorb_demand(q, d2, sat);
                    if (demand > 0u) {
                        ask(k, demand);
                    }
                }
                let m = force_scale(d2, s);
                if (m == 0.0) {
                    continue;
                }
                let g = m * d;
                acc += g;
                atomic_add_f32(4u * k, -g.x);
                atomic_add_f32(4u * k + 1u, -g.y);
                atomic_add_f32(4u * k + 2u, -g.z);
            }
        }
    }
    return acc;
}

// Pass water_integrate (cpu/water.rs `Water::integrate`): symplectic Euler for each particle
// with drag, the hair's reactions and gravity, then the colliders. Runs in grid order.
@compute @workgroup_size(WG)
fn water_integrate(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                   @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= grid[G_COUNT]) {
        return;
    }
    let p = sorted[k];
    let react = vec3<f32>(bitcast<f32>(atomicLoad(&water_force[4u * k])),
                          bitcast<f32>(atomicLoad(&water_force[4u * k + 1u])),
                          bitcast<f32>(atomicLoad(&water_force[4u * k + 2u])));
    var drag = P.water_drag;
    var inv_m = P.particle_inv_mass;
    if (P.massive != 0u) {
        // A held-water particle weighs its own water and its drag scales with it, so drops of
        // any size fall alike; an empty one (removed at the step's end) only falls.
        drag = f32(p.mass) * P.drag_per_quantum;
        inv_m = 0.0;
        if (p.mass != 0u) {
            inv_m = 1.0 / (f32(p.mass) * WATER_QUANTUM);
        }
    }
    let f = drag * (P.wind.xyz - p.v.xyz) + react;
    var v = p.v.xyz + P.h * (f * inv_m + P.g.xyz);
    var x = p.x.xyz + P.h * v;
    for (var c = 0u; c < N_COLLIDERS; c++) {
        collide(&x, &v, S.colliders[c], P.friction);
    }
    if (non_finite(dot(v, v) + x.x + x.y + x.z)) {
        atomicOr(&status[STATUS_FLAGS], FLAG_WATER_NONFINITE);
    }
    sorted[k] = Particle(x, p.mass, vec4<f32>(v, 0.0));
}
