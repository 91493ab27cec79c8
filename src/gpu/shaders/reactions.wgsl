// Eq. 2's reactions gathered by the particles (reaction_gathered.wgsl has the hair's side):
// after the hair kernel, the records of the points that had a particle within reach are
// sorted by their water-grid bucket (a counting sort: the kernel counted them; a prefix sum
// over the buckets; a scatter of their indices), and each particle sums, with no atomic, the
// reactions of its pairs: its own pull, stiffness and absorption sums, reckoned with
// pair.wgsl's laws from each point's record, so they equal the scatter form's to the bit.
// A pair is taken exactly when the hair's adhesion took it: the particle's cell lies in the
// point's query span and the pair is within reach, as both sides compute them.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> sorted: array<Particle>;
@group(0) @binding(2) var<storage, read> grid: array<u32>;
// The sums, the per-bucket counts and the points' records (reaction_gathered.wgsl).
@group(0) @binding(3) var<storage, read_write> wet: array<atomic<u32>>;
// The records' bucket starts (P.max_buckets + 1), the prefix sum's block sums, then the
// points' indices in bucket order.
@group(0) @binding(4) var<storage, read_write> wet_order: array<u32>;
// Absorption's per-particle scratch (buffers::absorb_words; a placeholder without absorption).
@group(0) @binding(5) var<storage, read_write> absorb_scratch: array<u32>;

// Where the indices in bucket order start in `wet_order`.
fn wet_list_at() -> u32 {
    return P.max_buckets + 1u + (P.max_buckets + SCAN_BLOCK - 1u) / SCAN_BLOCK;
}

// The counting sort's hooks (counting_scan.wgsl and scan.wgsl): bucket b's count and start,
// and the block sums after the starts.
fn count_of(b: u32) -> u32 {
    return atomicLoad(&wet[wet_counts_at() + b]);
}

fn start_of(b: u32) -> u32 {
    return wet_order[b];
}

fn set_start(b: u32, v: u32) {
    wet_order[b] = v;
}

fn block_sum(k: u32) -> u32 {
    return wet_order[P.max_buckets + 1u + k];
}

fn set_block_sum(k: u32, v: u32) {
    wet_order[P.max_buckets + 1u + k] = v;
}

// Pass reactions, part 1a: exclusive prefix sum of the records' counts within blocks of
// SCAN_BLOCK buckets (this substep's water grid has grid[G_BUCKETS]).
@compute @workgroup_size(256)
fn react_scan_blocks(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    scan_counts_block(wid.x, lid, grid[G_BUCKETS]);
}

// Pass reactions, part 1b (one workgroup): the block sums' prefix sum; the total closes the
// starts.
@compute @workgroup_size(256)
fn react_scan_sums(@builtin(local_invocation_index) lid: u32) {
    scan_block_totals(lid, grid[G_BUCKETS]);
}

// Pass reactions, part 1c: the block offsets added to every bucket's start.
@compute @workgroup_size(256)
fn react_scan_add(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    add_block_offset(wid.x, lid, grid[G_BUCKETS]);
}

// Pass reactions, part 2: each recorded point's index to its slot in bucket order (the counts
// drop back to 0 for the next substep). The order within a bucket is the atomics' and changes
// run to run; the sums below are integers, the same in any order.
@compute @workgroup_size(WG)
fn react_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                 @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    let key = atomicLoad(&wet[wet_record_at(i)]);
    if (key == 0u) {
        return;
    }
    let b = key - 1u;
    let slot = wet_order[b] + atomicSub(&wet[wet_counts_at() + b], 1u) - 1u;
    wet_order[wet_list_at() + slot] = i;
}

// Word w of point i's record as a float.
fn record_word(i: u32, w: u32) -> f32 {
    return bitcast<f32>(atomicLoad(&wet[wet_record_at(i) + w]));
}

// Pass reactions, part 3: each particle sums the reactions of its pairs (adhesion.wgsl's
// pairs, reckoned alike) into its sums, where water_integrate reads them; with absorption, the
// points' demands on it as `ask` summed them (their total and largest).
@compute @workgroup_size(WG)
fn react_gather(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= grid[G_COUNT]) {
        return;
    }
    let y = sorted[k].x.xyz;
    let q = sorted[k].mass;
    let s = strength_of(k);
    let r = P.r_max;
    let own = water_cell(y);
    // The cells of the points that may have taken this particle: those within reach, with a
    // margin for the rounding of the points' own spans and distances (a few f32 steps of the
    // coordinates). Cells are twice the reach, so that is 2 a side, 3 where rounding straddles
    // a face; the span is held to 3 a side, so that a particle too far out for f32 to resolve
    // the reach (or a non-finite one, which the hair kernel reports) cannot stall the kernel.
    let m = abs(y);
    let wide = r * 1.001 + max(max(m.x, m.y), m.z) * 5.0e-7;
    let c0 = water_cell(y - vec3<f32>(wide));
    let n = clamp(water_cell(y + vec3<f32>(wide)) - c0 + vec3<i32>(1), vec3<i32>(0), vec3<i32>(3));
    var acc = array<vec2<u32>, 3>(vec2<u32>(0u), vec2<u32>(0u), vec2<u32>(0u));
    var stiffness = 0u;
    var asked = vec2<u32>(0u);
    var best = 0u;
    let list = wet_list_at();
    for (var j = 0; j < n.x * n.y * n.z; j++) {
        let c = c0 + vec3<i32>(j / (n.y * n.z), (j / n.z) % n.y, j % n.z);
        let b = water_bucket(c);
        for (var t = wet_order[b]; t < wet_order[b + 1u]; t++) {
            let i = wet_order[list + t];
            let x = vec3<f32>(record_word(i, 1u), record_word(i, 2u), record_word(i, 3u));
            if (!in_cell(x, c)) {
                continue;
            }
            // The pair as adhesion took it: this particle's cell in the point's span, within
            // reach.
            let d = y - x;
            let d2 = dot(d, d);
            if (d2 > r * r || any(own < water_cell(x - vec3<f32>(r))) || any(own > water_cell(x + vec3<f32>(r)))) {
                continue;
            }
            let share = record_word(i, 4u);
            if (P.absorbs != 0u) {
                let demand = absorb_demand(q, d2, record_word(i, 5u), record_word(i, 6u));
                if (demand > 0u) {
                    asked = fixed_add(asked, vec2<u32>(demand, 0u));
                    best = max(best, demand);
                }
            }
            // A guide groom's point pulls back with its bundle's hair (adhesion.wgsl).
            let bundle = bundle_at(i);
            stiffness += stiffness_units(d2, share * bundle);
            let pull = force_scale(d2, s) * share;
            if (pull == 0.0) {
                continue;
            }
            let g = (pull * d) * bundle;
            for (var a = 0u; a < 3u; a++) {
                acc[a] = fixed_add(acc[a], fixed_neg(to_fixed(g[a])));
            }
        }
    }
    let at = WATER_FORCE_WORDS * k;
    for (var a = 0u; a < 3u; a++) {
        atomicStore(&wet[at + 2u * a], acc[a].x);
        atomicStore(&wet[at + 2u * a + 1u], acc[a].y);
    }
    atomicStore(&wet[at + 6u], stiffness);
    if (P.absorbs != 0u) {
        let ab = k * ABS_WORDS;
        absorb_scratch[ab + ABS_TOTAL] = asked.x;
        absorb_scratch[ab + ABS_TOTAL + 1u] = asked.y;
        absorb_scratch[ab + ABS_BEST] = best;
    }
}
