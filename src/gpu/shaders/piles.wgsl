// Drops that meet coalesce (cpu/piles.rs; docs/METHOD.md §2, "Drops that meet"), on the GPU.
//
// At a step's start the drops are grouped by the pile cell they lie in through a hash table of
// `pile_words::slots(n)` slots (a cell's first is its hash modulo their number): the first
// drop to claim a slot owns it, and stands for its cell's key (a drop whose cell hashes alike
// but differs probes on). Each cell's drops add
// their offsets from the cell's corner and their velocities to its slot in fixed point, as
// 64-bit word pairs by integer atomics (the units of cpu/piles.rs, so the sums are exact and
// the same in any order). Each occupied slot then makes one source: a particle at its drops'
// mean place with their mean velocity (the owner itself where the drops already share one
// place and velocity, or where it is alone), whose `mass` word counts its drops (eq. 2's
// strength and each drop's share of the reaction: adhesion.wgsl) and whose `left` word names
// its slot. The substeps' grid, eq. 2 and water_integrate see the sources in place of the
// drops, and at the step's end every drop takes its source's place and velocity. The CPU
// moves its drops source by source instead; both give each drop the same place and velocity
// (to the mean's last rounding), and nothing here depends on the order of the drops.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read_write> cur: array<Particle>;
@group(0) @binding(2) var<storage, read_write> other: array<Particle>;
@group(0) @binding(3) var<storage, read_write> water_state: array<atomic<u32>, WATER_STATE_WORDS>;
@group(0) @binding(4) var<storage, read_write> grid: array<u32>;
@group(0) @binding(5) var<storage, read_write> pile_table: array<atomic<u32>>;
// Each drop's slot in the table, by its index in the step's drops.
@group(0) @binding(6) var<storage, read_write> pile_slot: array<u32>;

// `pile_words::slots`: the table's slots for n drops (n is at most the capacity, 2^22).
fn pile_slots(n: u32) -> u32 {
    return max(PILE_MIN_SLOTS, n + n / 2u);
}

// cpu/piles.rs `Piles::group`'s cell: floor(x / cell) (beyond i32 saturates; the CPU's `as`
// does too).
fn pile_cell_of(x: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(x * P.pile_inv_cell));
}

// cpu/piles.rs `fixed_mean`'s rounding of one offset in units: to the nearest whole unit,
// halves away from zero (Rust's `round`), as a 64-bit two's-complement word pair.
fn to_units(q: f32) -> vec2<u32> {
    let m = abs(q);
    var r = floor(m);
    // Exact: below 2^23 the fraction and r + 1 are exact; above, m is whole.
    if (m - r >= 0.5) {
        r += 1.0;
    }
    let hi = floor(r / 4294967296.0);
    let w = vec2<u32>(u32(r - hi * 4294967296.0), u32(hi));
    return select(w, fixed_neg(w), q < 0.0);
}

// Adds a word pair to the 64-bit sum at word `at` of the table (low word first; the carry
// goes to the high word: exact in any order).
fn add_units(at: u32, w: vec2<u32>) {
    let old = atomicAdd(&pile_table[at], w.x);
    let high = carried_high(old, w);
    if (high != 0u) {
        atomicAdd(&pile_table[at + 1u], high);
    }
}

// The 64-bit sum at word `at` over n, in units.
fn mean_units(at: u32, n: u32) -> f32 {
    let s = vec2<u32>(atomicLoad(&pile_table[at]), atomicLoad(&pile_table[at + 1u]));
    let neg = (s.y & 0x80000000u) != 0u;
    let m = select(s, fixed_neg(s), neg);
    let v = (f32(m.y) * 4294967296.0 + f32(m.x)) / f32(n);
    return select(v, -v, neg);
}

// Pass water_grid's piles, part 1: the table cleared for this step's drops.
@compute @workgroup_size(WG)
fn pile_clear(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
              @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= pile_slots(atomicLoad(&water_state[WATER_HELD]))) {
        return;
    }
    atomicStore(&pile_table[i * PILE_WORDS + PILE_OWNER], PILE_EMPTY);
    for (var w = 1u; w < PILE_WORDS; w++) {
        atomicStore(&pile_table[i * PILE_WORDS + w], 0u);
    }
}

// Pass water_grid's piles, part 2: each drop finds its cell's slot (claiming it if empty),
// counts itself there, adds its offset and velocity, and marks the slot apart when it differs
// from the owner.
@compute @workgroup_size(WG)
fn pile_insert(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
               @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    let n = atomicLoad(&water_state[WATER_HELD]);
    if (i >= n) {
        return;
    }
    let slots = pile_slots(n);
    let p = cur[i];
    let c = pile_cell_of(p.x);
    var h = hash_cell(c) % slots;
    var owner = i;
    loop {
        let r = atomicCompareExchangeWeak(&pile_table[h * PILE_WORDS + PILE_OWNER], PILE_EMPTY, i);
        if (r.exchanged) {
            break;
        }
        // A weak exchange may fail on an empty slot: try it again.
        if (r.old_value != PILE_EMPTY) {
            if (all(pile_cell_of(cur[r.old_value].x) == c)) {
                owner = r.old_value;
                break;
            }
            h = select(h + 1u, 0u, h + 1u == slots);
        }
    }
    pile_slot[i] = h;
    let at = h * PILE_WORDS;
    atomicAdd(&pile_table[at + PILE_COUNT], 1u);
    let o = cur[owner];
    if (any(o.x != p.x) || any(o.v != p.v)) {
        atomicOr(&pile_table[at + PILE_APART], 1u);
    }
    let corner = vec3<f32>(c) * P.pile_cell;
    let q = (p.x - corner) * P.pile_inv_unit;
    let u = p.v * (1.0 / PILE_VELOCITY_UNIT);
    for (var a = 0u; a < 3u; a++) {
        add_units(at + PILE_SUM_X + 2u * a, to_units(q[a]));
        add_units(at + PILE_SUM_V + 2u * a, to_units(u[a]));
    }
}

// Pass water_grid's piles, part 3: each occupied slot makes its source in the other buffer.
@compute @workgroup_size(WG)
fn pile_sources(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let h = linear_id(wid, nwg, lid);
    if (h >= pile_slots(atomicLoad(&water_state[WATER_HELD]))) {
        return;
    }
    let at = h * PILE_WORDS;
    let owner = atomicLoad(&pile_table[at + PILE_OWNER]);
    if (owner == PILE_EMPTY) {
        return;
    }
    let n = atomicLoad(&pile_table[at + PILE_COUNT]);
    var x = cur[owner].x;
    var v = cur[owner].v;
    // Drops that already share one place and velocity are left as they are (their mean is
    // themselves), so a pile is not rounded again each step.
    if (n > 1u && atomicLoad(&pile_table[at + PILE_APART]) != 0u) {
        let corner = vec3<f32>(pile_cell_of(x)) * P.pile_cell;
        var mx = vec3<f32>(0.0);
        var mv = vec3<f32>(0.0);
        for (var a = 0u; a < 3u; a++) {
            mx[a] = mean_units(at + PILE_SUM_X + 2u * a, n);
            mv[a] = mean_units(at + PILE_SUM_V + 2u * a, n);
        }
        x = corner + mx * P.pile_unit;
        v = mv * PILE_VELOCITY_UNIT;
    }
    let s = atomicAdd(&water_state[WATER_SOURCES], 1u);
    other[s] = Particle(x, n, v, h);
    atomicMax(&water_state[WATER_PILE_MAX], n);
}

// Pass water_grid's piles, part 4 (one invocation): the sources become the particles the
// substeps see; the drops' count waits for the step's end, and the largest pile goes to the
// grid's header for eq. 2's stability limit (adhesion.wgsl `limited_weight`).
@compute @workgroup_size(1)
fn pile_finish() {
    atomicStore(&water_state[WATER_DROPS], atomicLoad(&water_state[WATER_HELD]));
    atomicStore(&water_state[WATER_HELD], atomicLoad(&water_state[WATER_SOURCES]));
    atomicStore(&water_state[WATER_SOURCES], 0u);
    grid[G_PILE_MAX] = atomicLoad(&water_state[WATER_PILE_MAX]);
    atomicStore(&water_state[WATER_PILE_MAX], 0u);
}

// Pass pile_spread, part 1: each source leaves its place and velocity in its slot.
@compute @workgroup_size(WG)
fn pile_spread_sources(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                       @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= atomicLoad(&water_state[WATER_HELD])) {
        return;
    }
    let p = cur[k];
    let at = p.left * PILE_WORDS;
    for (var a = 0u; a < 3u; a++) {
        atomicStore(&pile_table[at + PILE_PLACE + a], bitcast<u32>(p.x[a]));
        atomicStore(&pile_table[at + PILE_VEL + a], bitcast<u32>(p.v[a]));
    }
}

// Pass pile_spread, part 2: each drop takes its source's place and velocity.
@compute @workgroup_size(WG)
fn pile_spread_drops(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                     @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= atomicLoad(&water_state[WATER_DROPS])) {
        return;
    }
    let at = pile_slot[i] * PILE_WORDS;
    var x = vec3<f32>(0.0);
    var v = vec3<f32>(0.0);
    for (var a = 0u; a < 3u; a++) {
        x[a] = bitcast<f32>(atomicLoad(&pile_table[at + PILE_PLACE + a]));
        v[a] = bitcast<f32>(atomicLoad(&pile_table[at + PILE_VEL + a]));
    }
    other[i] = Particle(x, 0u, v, 0u);
}

// Pass pile_spread, part 3 (one invocation): the drops are the particles again.
@compute @workgroup_size(1)
fn pile_spread_finish() {
    atomicStore(&water_state[WATER_HELD], atomicLoad(&water_state[WATER_DROPS]));
    atomicStore(&water_state[WATER_DROPS], 0u);
}
