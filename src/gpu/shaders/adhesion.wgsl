// Eq. 2 on the GPU (physics/adhesion.rs): each hair point gathers the particles of the grid
// cells within r_max; the opposite force goes to the particle with a float atomic add, so
// hair and water exchange exactly equal and opposite forces (up to summation order).

@group(1) @binding(0) var<storage, read_write> sorted: array<Particle>;
@group(1) @binding(1) var<storage, read_write> water_force: array<atomic<u32>>;
@group(1) @binding(2) var<storage, read> grid: array<u32>;

// Eq. 2's factor (physics/adhesion.rs `force_scale`): s g(d) / d within [MIN_DISTANCE, r_max], else 0.
fn force_scale(d2: f32) -> f32 {
    if (d2 > P.r_max * P.r_max || d2 < MIN_DISTANCE * MIN_DISTANCE) {
        return 0.0;
    }
    let d = sqrt(d2);
    let u = (2.0 * d - P.r_min - P.r_max) / (P.r_min - P.r_max);
    return P.adhesion * (1.0 - u * u) / d;
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

// Pass adhesion: returns the force on the hair point and sets `near` when a particle is
// within r_max (for wetting).
fn adhesion(x: vec3<f32>, near: ptr<function, f32>) -> vec3<f32> {
    var acc = vec3<f32>(0.0);
    if (grid[G_COUNT] == 0u) {
        return acc;
    }
    let lo = grid_lo();
    let inv = bitcast<f32>(grid[G_INV]);
    let dims = grid_dims();
    let r = P.r_max;
    // Outside the particles' box grown by r_max no particle can be near (Grid::may_have_near
    // on the CPU); without this test, clamping would send every far point to scan the
    // boundary cells.
    let hi = lo + vec3<f32>(dims) * bitcast<f32>(grid[G_CELL]);
    if (any(x < lo - vec3<f32>(r)) || any(x > hi + vec3<f32>(r))) {
        return acc;
    }
    let c0 = cell_of(x - vec3<f32>(r), lo, inv, dims);
    let c1 = cell_of(x + vec3<f32>(r), lo, inv, dims);
    for (var cx = c0.x; cx <= c1.x; cx++) {
        for (var cy = c0.y; cy <= c1.y; cy++) {
            let row = (cx * dims.y + cy) * dims.z;
            let s = grid[G_START + u32(row + c0.z)];
            let e = grid[G_START + u32(row + c1.z) + 1u];
            for (var k = s; k < e; k++) {
                let d = sorted[k].x.xyz - x;
                let d2 = dot(d, d);
                if (d2 > r * r) {
                    continue;
                }
                *near = 1.0;
                let m = force_scale(d2);
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
