// Eq. 2 on the GPU (physics/adhesion.rs): each hair point gathers the particles of the grid
// cells within r_max (grid.wgsl); the opposite force goes to the particle by integer atomic
// adds (reaction64.wgsl or reaction32.wgsl), or the particles gather it from the records the
// points leave (reaction_gathered.wgsl, reactions.wgsl). Both sides sum in 64-bit fixed point
// (FIXED_SCALE units per adhesion strength), so a sum is the same whatever order the
// particles of a cell, or the points that pull one particle, come in: a step gives the same
// bits run after run, and hair and water exchange exactly equal and opposite forces up to the
// one rounding back to f32.

@group(1) @binding(0) var<storage, read_write> sorted: array<Particle>;
// Binding 1, the particles' reaction sums, and their adds come from reaction32.wgsl,
// reaction64.wgsl or reaction_gathered.wgsl.
@group(1) @binding(2) var<storage, read> grid: array<u32>;
// Absorption's per-particle scratch (buffers::absorb_words; a placeholder without absorption).
@group(1) @binding(3) var<storage, read_write> absorb_scratch: array<atomic<u32>>;

// Particle k's reaction in newtons.
fn reaction(k: u32) -> vec3<f32> {
    return vec3<f32>(from_fixed(reaction_sum(k, 0u)), from_fixed(reaction_sum(k, 1u)), from_fixed(reaction_sum(k, 2u)));
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

// Marks point i as having had a particle within r_max this substep (absorption only), so the
// absorb pass visits it; absorb clears the bit.
fn mark_near(i: u32) {
    atomicOr(&absorb_scratch[near_word(i)], near_bit(i));
}

// physics/pull_limit.rs `pull_limit`: the factor on a hair point's pulls, 1 while
// q = slope_h2 stiffness weight inv_mass stays within the limit, else LIMIT / q.
fn pull_limit(stiffness: f32, weight: f32, inv_mass: f32) -> f32 {
    let q = P.pull_slope_h2 * stiffness * weight * inv_mass;
    if (q > PULL_STIFFNESS_LIMIT) {
        return PULL_STIFFNESS_LIMIT / q;
    }
    return 1.0;
}

// physics/pull_limit.rs `particle_limit`: the factor on a particle's response to its
// forces, from how stiffly the hair holds it (`stiffness`) and its strength over its mass
// (eq. 2's s over a full particle's mass, whatever water it holds).
fn particle_limit(stiffness: f32) -> f32 {
    return pull_limit(P.adhesion * P.particle_inv_mass, stiffness, 1.0);
}

// physics/pull_limit.rs `PullLimit::row_weights` for one point: its weight with the limit
// applied, from the particles of the span within r_max. A point whose cells hold at most
// `pull_free` candidates skips the count (it cannot reach the limit); a source of several
// drops pulls as that many, so the count is divided by the largest pile.
fn limited_weight(i: u32, x: vec3<f32>, span: Span, weight: f32) -> f32 {
    let inv_mass = points[i].inv_mass;
    if (weight == 0.0 || inv_mass == 0.0) {
        return weight;
    }
    let r = P.r_max;
    var candidates = 0u;
    for (var j = 0; j < span_cells(span); j++) {
        let run = cell_run(span_cell(span, j));
        candidates += run.y - run.x;
    }
    if (candidates <= P.pull_free / max(grid[G_PILE_MAX], 1u)) {
        return weight;
    }
    // stiffness_in_reach: each particle's strength times the pair's stiffness, summed in the
    // reactions' 64-bit fixed point, so the sum is the same in whatever order the atomics of
    // the grid's scatter left a bucket's particles (an f32 sum in that order made wet runs
    // differ in their last bits run to run, found 2026-12-03).
    var stiffness = vec2<u32>(0u);
    for (var j = 0; j < span_cells(span); j++) {
        let c = span_cell(span, j);
        let run = cell_run(c);
        for (var k = run.x; k < run.y; k++) {
            let y = sorted[k].x.xyz;
            let d = y - x;
            let d2 = dot(d, d);
            if (d2 <= r * r && in_cell(y, c)) {
                stiffness = fixed_add(stiffness, to_fixed(strength_of(k) * pair_stiffness(d2)));
            }
        }
    }
    return weight * pull_limit(from_fixed(stiffness), weight, inv_mass);
}

// Pass adhesion: returns the force on hair point i at x and sets `near` when a particle is
// within r_max (for wetting). With absorption, a particle pulls with the water it still holds
// and the point (at saturation `sat`) asks it for water.
fn adhesion(i: u32, x: vec3<f32>, sat: f32, near: ptr<function, f32>) -> vec3<f32> {
    var acc = array<vec2<u32>, 3>(vec2<u32>(0u), vec2<u32>(0u), vec2<u32>(0u));
    var bad = false;
    let r = P.r_max;
    var span: Span;
    if (!near_span(x, r, &span)) {
        note_wet(i, x, 0.0, 0.0, 0.0, false);
        return vec3<f32>(0.0);
    }
    var take = 0.0;
    if (P.absorbs != 0u) {
        take = absorb_take_at(i);
    }
    // The point's share of each pull (physics/per_length.rs: the CPU's lane weight).
    var share = 1.0;
    if (P.adhesion_scale > 0.0) {
        share = rest_around(i) * P.adhesion_scale;
    }
    // Its stability limit (physics/pull_limit.rs).
    share = limited_weight(i, x, span, share);
    // In a guide groom the point stands for its bundle's strands: it pulls each particle
    // back with their hair (the CPU's `bundle` lanes; 1 otherwise).
    let bundle = bundle_at(i);
    for (var j = 0; j < span_cells(span); j++) {
        let c = span_cell(span, j);
        let run = cell_run(c);
        for (var k = run.x; k < run.y; k++) {
            let y = sorted[k].x.xyz;
            let d = y - x;
            let d2 = dot(d, d);
            if (d2 > r * r || !in_cell(y, c)) {
                continue;
            }
            *near = 1.0;
            let s = strength_of(k);
            // Where the particles gather, react_gather reckons these from the point's record.
            if (!GATHERED) {
                if (P.absorbs != 0u) {
                    let q = sorted[k].mass;
                    let demand = absorb_demand(q, d2, sat, take);
                    if (demand > 0u) {
                        ask(k, demand);
                    }
                }
                // How stiffly the point holds the particle, for its side of the stability limit.
                let stiff = stiffness_units(d2, share * bundle);
                if (stiff != 0u) {
                    add_stiffness(k, stiff);
                }
            }
            let m = force_scale(d2, s) * share;
            if (m == 0.0) {
                continue;
            }
            let g = m * d;
            // A non-finite pull has no fixed-point form: it is flagged, and the point's
            // force is made non-finite below, so the kernel reports it as before.
            bad = bad || non_finite(dot(g, g));
            let r = g * bundle;
            for (var a = 0u; a < 3u; a++) {
                acc[a] = fixed_add(acc[a], to_fixed(g[a]));
                if (!GATHERED) {
                    add_reaction(k, a, fixed_neg(to_fixed(r[a])));
                }
            }
        }
    }
    note_wet(i, x, share, sat, take, *near != 0.0);
    if (bad) {
        atomicOr(&status[STATUS_FLAGS], FLAG_WATER_NONFINITE);
        return vec3<f32>(bitcast<f32>(0x7fc00000u));
    }
    return vec3<f32>(from_fixed(acc[0]), from_fixed(acc[1]), from_fixed(acc[2]));
}

// physics/integrate.rs `particle_velocity`: a particle's velocity after a substep h, its drag
// (rate k toward the wind) taken implicitly, `a` every other acceleration.
fn particle_velocity(v: vec3<f32>, a: vec3<f32>, k: f32, wind: vec3<f32>, h: f32) -> vec3<f32> {
    return (v + h * (a + k * wind)) / (1.0 + h * k);
}

// Pass water_integrate (cpu/water.rs `Water::integrate`): symplectic Euler for each particle
// with the hair's reactions and gravity, its drag taken implicitly, then the colliders. Runs
// in grid order.
@compute @workgroup_size(WG)
fn water_integrate(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                   @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= grid[G_COUNT]) {
        return;
    }
    let p = sorted[k];
    let react = reaction(k);
    var inv_m = P.particle_inv_mass;
    if (P.massive != 0u) {
        // A held-water particle weighs the water it held when the hair's pull on it was
        // reckoned, at the substep's start (cpu/water.rs `integrate`), and its drag scales
        // with it, so drops of any size slow at a full particle's rate and fall alike; an
        // empty one (removed at the step's end) only falls.
        inv_m = 0.0;
        if (p.mass != 0u) {
            inv_m = 1.0 / (f32(p.mass) * WATER_QUANTUM);
        }
    }
    let stiffness = f32(stiffness_sum(k)) / STIFFNESS_SCALE;
    // The sums start at zero for the next substep's hair kernel.
    clear_reactions(k);
    var rate = 0.0;
    // Its side of eq. 2's stability limit: held by more hair than a substep follows, it
    // responds to its forces more slowly, its drag damping it at its own rate
    // (physics/pull_limit.rs `particle_limit`).
    var factor = 1.0;
    if (inv_m > 0.0) {
        rate = P.water_drag_rate;
        factor = particle_limit(stiffness);
    }
    // A source of coalesced drops moves as each of them: an equal share of its reaction on
    // a drop's mass (piles.wgsl; cpu/water.rs `integrate` with `Piles::share`).
    var force = react;
    var left = 0u;
    if (P.pile_cell > 0.0) {
        force = react / f32(p.mass);
        left = p.left;
    }
    let a = factor * (force * inv_m + P.g.xyz);
    var v = particle_velocity(p.v.xyz, a, rate, factor * P.wind.xyz, P.h);
    var x = p.x.xyz + P.h * v;
    for (var c = 0u; c < N_COLLIDERS; c++) {
        collide(&x, &v, S.colliders[c], P.friction);
    }
    if (non_finite(dot(v, v) + x.x + x.y + x.z)) {
        atomicOr(&status[STATUS_FLAGS], FLAG_WATER_NONFINITE);
    }
    // What absorb_finish left is the particle's water from here on.
    var mass = p.mass;
    if (P.absorbs != 0u) {
        mass = p.left;
    }
    sorted[k] = Particle(x, mass, v, left);
}
