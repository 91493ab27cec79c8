// The water passes (cpu/water.rs and physics/hash_grid.rs): append new particles, rebuild the
// hashed grid by counting sort (bounds, setup, count, prefix sum, scatter into bucket
// order), and remove particles that left the domain. The scatter writes the particles in grid
// order into the other buffer, which the hair substep then reads and water_integrate updates.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read_write> cur: array<Particle>;
@group(0) @binding(2) var<storage, read_write> other: array<Particle>;
// The grid's mark table (physics/hash_marks.rs): the `grid` buffer from word G_MARK_AT on,
// bound apart so that it can be set by atomic or.
@group(0) @binding(3) var<storage, read_write> grid_marks: array<atomic<u32>>;
// [0..3) max of ~key(lo), [3..6) max of key(hi), [GRID_COUNT_HEADER + b] particles in bucket b.
@group(0) @binding(4) var<storage, read_write> grid_count: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> grid: array<u32>;
// [WATER_HELD] particles, [WATER_KEPT] kept by the cull, [WATER_REMOVED] removed since reset,
// [WATER_LEFT] (lo, hi) their water in quanta (held water).
@group(0) @binding(6) var<storage, read_write> water_state: array<atomic<u32>, WATER_STATE_WORDS>;
@group(0) @binding(7) var<storage, read> incoming: array<Particle>;
// The prefix sum's indirect dispatch size: bound only for grid_setup, as a buffer cannot be
// storage and indirect in one dispatch.
@group(1) @binding(0) var<storage, read_write> grid_dispatch: array<u32, 3>;

// Word w of the grid's mark table (grid.wgsl `marked`).
fn mark_word(w: u32) -> u32 {
    return atomicLoad(&grid_marks[w]);
}

// Float bits mapped so that unsigned order is float order.
fn order_key(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    if ((b & 0x80000000u) != 0u) {
        return ~b;
    }
    return b | 0x80000000u;
}

fn order_value(k: u32) -> f32 {
    if ((k & 0x80000000u) != 0u) {
        return bitcast<f32>(k & 0x7fffffffu);
    }
    return bitcast<f32>(~k);
}

// Pass water_append: new particles go after the live ones.
@compute @workgroup_size(WG)
fn water_append(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.incoming) {
        return;
    }
    let slot = atomicAdd(&water_state[WATER_HELD], 1u);
    if (slot < P.capacity) {
        cur[slot] = incoming[i];
    }
}

var<workgroup> wg_bounds: array<atomic<u32>, 6>;

// Pass water_grid, part 1: the particles' bounds (a workgroup reduction, then one atomic per
// workgroup and axis), and the last build's mark table cleared (the hair read it after that
// build; this one marks it again).
@compute @workgroup_size(WG)
fn grid_bounds(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
               @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    let marks = grid[G_MARKS];
    for (var w = i; w < marks; w += nwg.x * nwg.y * WG) {
        atomicStore(&grid_marks[w], 0u);
    }
    if (i < atomicLoad(&water_state[WATER_HELD])) {
        let x = cur[i].x.xyz;
        for (var a = 0u; a < 3u; a++) {
            atomicMax(&wg_bounds[a], ~order_key(x[a]));
            atomicMax(&wg_bounds[3u + a], order_key(x[a]));
        }
    }
    workgroupBarrier();
    if (lid < 6u) {
        let k = atomicLoad(&wg_bounds[lid]);
        if (k != 0u) {
            atomicMax(&grid_count[lid], k);
        }
    }
}

// Pass water_grid, part 2 (one invocation): the box (for the queries' early out), the cell
// side and the table of `HashGrid::build` (hash_grid::buckets_for); the prefix sum's indirect
// dispatch size; bounds cleared for the next build.
@compute @workgroup_size(1)
fn grid_setup() {
    let n = atomicLoad(&water_state[WATER_HELD]);
    var lo = vec3<f32>(0.0);
    var hi = vec3<f32>(0.0);
    if (n > 0u) {
        for (var a = 0u; a < 3u; a++) {
            lo[a] = order_value(~atomicLoad(&grid_count[a]));
            hi[a] = order_value(atomicLoad(&grid_count[3u + a]));
        }
    }
    // The next power of two of 2n, at least MIN_BUCKETS (n <= capacity: within max_buckets).
    let buckets = max(MIN_BUCKETS, 1u << (32u - countLeadingZeros(max(2u * n, 2u) - 1u)));
    let cell = WATER_CELL_R * P.r_max;
    for (var a = 0u; a < 3u; a++) {
        grid[G_LO + a] = bitcast<u32>(lo[a]);
        grid[G_HI + a] = bitcast<u32>(hi[a]);
        atomicStore(&grid_count[a], 0u);
        atomicStore(&grid_count[3u + a], 0u);
    }
    grid[G_CELL] = bitcast<u32>(cell);
    grid[G_INV] = bitcast<u32>(1.0 / cell);
    grid[G_BUCKETS] = buckets;
    grid[G_COUNT] = n;
    // hash_marks::mark_words: 4 words a bucket up to the cap; none past half a word a particle.
    var marks = min(MARK_WORDS_PER_BUCKET * buckets, MAX_MARK_WORDS);
    if (n > marks / 2u) {
        marks = 0u;
    }
    grid[G_MARKS] = marks;
    grid_dispatch[0] = (buckets + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    grid_dispatch[1] = 1u;
    grid_dispatch[2] = 1u;
}

// The bucket of the particle at x.
fn bucket_at(x: vec3<f32>) -> u32 {
    return water_bucket(water_cell(x));
}

// hash_marks::mark_span: the particle at y marks its cell and, along each axis, the
// neighbour across each face it lies within half a cell and MARK_MARGIN of.
fn mark_particle(y: vec3<f32>, words: u32) {
    let q = y * bitcast<f32>(grid[G_INV]);
    let c = water_cell(y);
    let f = q - floor(q);
    let lo = c - select(vec3<i32>(0), vec3<i32>(1), f < vec3<f32>(0.5 + MARK_MARGIN));
    let hi = c + select(vec3<i32>(0), vec3<i32>(1), f > vec3<f32>(0.5 - MARK_MARGIN));
    // By offsets from lo (0 to 2 a side, wrapping as the span does), so a cell at the edge
    // of i32 cannot make the loop run on.
    let n = hi - lo;
    for (var a = 0; a <= n.x; a++) {
        for (var b = 0; b <= n.y; b++) {
            for (var k = 0; k <= n.z; k++) {
                let m = mark_bit(lo + vec3<i32>(a, b, k), words);
                atomicOr(&grid_marks[m.x], 1u << m.y);
            }
        }
    }
}

// Pass water_grid, part 3: particles per bucket, and the cells they mark.
@compute @workgroup_size(WG)
fn grid_count_cells(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                    @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= grid[G_COUNT]) {
        return;
    }
    let y = cur[i].x.xyz;
    atomicAdd(&grid_count[GRID_COUNT_HEADER + bucket_at(y)], 1u);
    let words = grid[G_MARKS];
    if (words != 0u) {
        mark_particle(y, words);
    }
}

// The counting sort's hooks (counting_scan.wgsl): bucket b's count and start.
fn count_of(b: u32) -> u32 {
    return atomicLoad(&grid_count[GRID_COUNT_HEADER + b]);
}

fn start_of(b: u32) -> u32 {
    return grid[G_START + b];
}

fn set_start(b: u32, v: u32) {
    grid[G_START + b] = v;
}

// Pass water_grid, part 4a: exclusive prefix sum of the counts within blocks of 1,024
// buckets.
@compute @workgroup_size(256)
fn grid_scan_blocks(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    scan_counts_block(wid.x, lid, grid[G_BUCKETS]);
}

// The scan's block sums, after start[0..=max_buckets] (scan.wgsl `scan_block_sums`).
fn block_sum(k: u32) -> u32 {
    return grid[G_START + P.max_buckets + 1u + k];
}

fn set_block_sum(k: u32, v: u32) {
    grid[G_START + P.max_buckets + 1u + k] = v;
}

// Pass water_grid, part 4b (one workgroup): exclusive prefix sum of the block sums; the
// total closes the starts.
@compute @workgroup_size(256)
fn grid_scan_sums(@builtin(local_invocation_index) lid: u32) {
    scan_block_totals(lid, grid[G_BUCKETS]);
}

// Pass water_grid, part 4c: block offsets added to every bucket's start.
@compute @workgroup_size(256)
fn grid_scan_add(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    add_block_offset(wid.x, lid, grid[G_BUCKETS]);
}

// Pass water_grid, part 5: each particle to its slot in bucket order (counts drop back to 0,
// ready for the next build; the slot's reaction sums are 0, as water_integrate left them).
@compute @workgroup_size(WG)
fn grid_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= grid[G_COUNT]) {
        return;
    }
    let p = cur[i];
    let c = bucket_at(p.x.xyz);
    let slot = grid[G_START + c] + atomicSub(&grid_count[GRID_COUNT_HEADER + c], 1u) - 1u;
    other[slot] = p;
}

// Pass water_cull (once per step): particles farther than the domain radius from its centre
// are dropped (with held water, so are those the hair emptied, and the water of those that
// leave is booked as left); the rest are compacted into the other buffer.
@compute @workgroup_size(WG)
fn water_cull(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
              @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= atomicLoad(&water_state[WATER_HELD])) {
        return;
    }
    let p = cur[i];
    let d = p.x.xyz - P.domain_center.xyz;
    let empty = P.massive != 0u && p.mass == 0u;
    if (dot(d, d) > P.domain_r2 || empty) {
        atomicAdd(&water_state[WATER_REMOVED], 1u);
        let old = atomicAdd(&water_state[WATER_LEFT], p.mass);
        if (old + p.mass < old) {
            atomicAdd(&water_state[WATER_LEFT + 1u], 1u);
        }
        return;
    }
    other[atomicAdd(&water_state[WATER_KEPT], 1u)] = p;
}

// Pass water_cull, part 2 (one invocation): the kept count becomes the count.
@compute @workgroup_size(1)
fn water_cull_finish() {
    atomicStore(&water_state[WATER_HELD], atomicLoad(&water_state[WATER_KEPT]));
    atomicStore(&water_state[WATER_KEPT], 0u);
}
