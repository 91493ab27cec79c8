// Liquid bridges on the GPU, pass hair_grid (cpu/bridges.rs `find_pairs`; docs/WET_MODEL.md
// §5), once per step over the state at its start: a hashed grid of the wet free points
// (bridge_count, bridge_scan_blocks, bridge_scan_sums, bridge_scan_add, bridge_scatter), this
// turn's searches for each point's nearest wet points of other strands (bridge_search_setup,
// bridge_search), the mutual pairs (bridge_pairs) and their coefficients (bridge_coef). Pass
// cohesion, which pulls, is in the hair module (cohesion.wgsl): it binds the hair's state.
// Points are numbered as the host numbers them, as the CPU's search turns and tie-breaks count
// them.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> points: array<Point>;
@group(0) @binding(2) var<storage, read> held: array<u32>;
@group(0) @binding(3) var<storage, read> capacity: array<u32>;
@group(0) @binding(4) var<storage, read> state: array<State>;
// Wet points per bucket; zero between builds (the scatter counts them back down). One more
// word, at BRIDGE_BUCKETS: the points listed to search this step (zeroed when the list is
// taken, bridge_search_setup).
@group(0) @binding(5) var<storage, read_write> bucket_count: array<atomic<u32>>;
// [0, BRIDGE_BUCKETS]: each bucket's first entry (the last word: the total); then each scan
// block's sum; then the entries, point indices by bucket; then how many points search this
// step, and those points (in any order: each search writes its own point's record only).
@group(0) @binding(6) var<storage, read_write> bucket: array<u32>;
// Per point, BR_WORDS words (buffers.rs `bridge_words`); then, from word P.bridge_masks, each
// point's mask of mutual bridges; then each point's flag: 1 while it takes part.
@group(0) @binding(7) var<storage, read_write> bridge: array<u32>;

const B_SUMS: u32 = BRIDGE_BUCKETS + 1u;
const B_ENTRIES: u32 = B_SUMS + BRIDGE_BLOCKS;
// The search's indirect dispatch size: bound only for bridge_search_setup, as a buffer cannot
// be storage and indirect in one dispatch.
@group(1) @binding(0) var<storage, read_write> search_dispatch: array<u32, 3>;

const B_SEARCHES: u32 = B_ENTRIES + BRIDGE_POINTS;
const B_SEARCH_LIST: u32 = B_SEARCHES + 1u;
const SEARCH_LISTED: u32 = BRIDGE_BUCKETS;

// Farther than any distance: the empty slots of a search.
const FAR: f32 = 3.4028235e38;

// wet::can_bridge: any water, and at least capacity / BRIDGE_MIN_PARTS rounded up.
fn can_bridge(w: u32, cap: u32) -> bool {
    let least = cap / BRIDGE_MIN_PARTS + select(0u, 1u, cap % BRIDGE_MIN_PARTS != 0u);
    return w > 0u && w >= least;
}

// Whether point i takes part: free (a bridge cannot move a root) and holding water enough.
fn bridge_point(i: u32) -> bool {
    return can_bridge(held[i], capacity[i]) && points[i].inv_mass > 0.0;
}

// HashGrid::coord_of: the cell of side d_b holding x (floor; beyond i32 saturates).
fn bridge_cell(x: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(x * (1.0 / P.bridge_length)));
}

// HashGrid::bucket_of over the bridges' table.
fn bucket_of(c: vec3<i32>) -> u32 {
    return hash_cell(c) & (BRIDGE_BUCKETS - 1u);
}

// Point i's flag word: 0 while it takes no part; FLAG_PART from bridge_count when it starts
// to, FLAG_SEARCHED from its first search since (physics/wet.rs `bridge_searches`).
const FLAG_PART: u32 = 1u;
const FLAG_SEARCHED: u32 = 2u;
fn flag_at(i: u32) -> u32 {
    return P.bridge_masks + BRIDGE_POINTS + i;
}

// Whether point i takes part this step, as bridge_count found (held water, capacities and
// records do not change within pass hair_grid).
fn taking_part(i: u32) -> bool {
    return bridge[flag_at(i)] != 0u;
}

// physics/wet.rs `bridge_searches`: whether point i, taking part, searches this step: its
// turn, or it has searched since it became wet (`flag` FLAG_SEARCHED) and has no neighbour;
// one that has just become wet waits for its turn.
fn searches(i: u32, flag: u32) -> bool {
    return i % BRIDGE_SEARCH_TURNS == P.bridge_turn || (bridge[i * BR_WORDS + BR_COUNT] == 0u && flag == FLAG_SEARCHED);
}

// Pass hair_grid, part 1: wet points per bucket, each point's flag, and the list of the points
// that search; a point that has just stopped taking part forgets its nearest and its bridges
// (one that had not taken part has neither, so most points read their water, capacity and
// flag, and write nothing).
@compute @workgroup_size(WG)
fn bridge_count(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points) {
        return;
    }
    let part = bridge_point(i);
    let flag = bridge[flag_at(i)];
    let was = flag != 0u;
    if (part != was) {
        bridge[flag_at(i)] = select(0u, FLAG_PART, part);
    }
    if (!part) {
        if (was) {
            bridge[i * BR_WORDS + BR_COUNT] = 0u;
            bridge[P.bridge_masks + i] = 0u;
        }
        return;
    }
    atomicAdd(&bucket_count[bucket_of(bridge_cell(state[i].x.xyz))], 1u);
    if (searches(i, flag)) {
        bucket[B_SEARCH_LIST + atomicAdd(&bucket_count[SEARCH_LISTED], 1u)] = i;
    }
}

// The counting sort's hooks (counting_scan.wgsl): bucket b's count and start.
fn count_of(b: u32) -> u32 {
    return atomicLoad(&bucket_count[b]);
}

fn start_of(b: u32) -> u32 {
    return bucket[b];
}

fn set_start(b: u32, v: u32) {
    bucket[b] = v;
}

// Pass hair_grid, part 2a: exclusive prefix sum of the counts within blocks of SCAN_BLOCK
// buckets (BRIDGE_BUCKETS is a multiple of it).
@compute @workgroup_size(256)
fn bridge_scan_blocks(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    scan_counts_block(wid.x, lid, BRIDGE_BUCKETS);
}

// The scan's block sums (scan.wgsl `scan_block_sums`).
fn block_sum(k: u32) -> u32 {
    return bucket[B_SUMS + k];
}

fn set_block_sum(k: u32, v: u32) {
    bucket[B_SUMS + k] = v;
}

// Pass hair_grid, part 2b (one workgroup): exclusive prefix sum of the block sums; the total
// closes the starts.
@compute @workgroup_size(256)
fn bridge_scan_sums(@builtin(local_invocation_index) lid: u32) {
    scan_block_totals(lid, BRIDGE_BUCKETS);
}

// Pass hair_grid, part 2c: each block's offset added to its buckets' starts.
@compute @workgroup_size(256)
fn bridge_scan_add(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    add_block_offset(wid.x, lid, BRIDGE_BUCKETS);
}

// Pass hair_grid, part 3: each wet point into its bucket (in any order within it: a search
// keeps its nearest by a strict order, so the order it visits them in does not matter).
@compute @workgroup_size(WG)
fn bridge_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || !taking_part(i)) {
        return;
    }
    let b = bucket_of(bridge_cell(state[i].x.xyz));
    let slot = bucket[b] + atomicSub(&bucket_count[b], 1u) - 1u;
    bucket[B_ENTRIES + slot] = i;
}

// A search's few nearest so far, nearest first (cpu/bridges.rs `nearest_of`).
var<private> best_d: array<f32, MAX_BRIDGES>;
var<private> best_q: array<u32, MAX_BRIDGES>;
var<private> best_n: u32;

// Whether (d2, q) comes before the k-th nearest: nearer, or as near with a lower index.
fn closer(k: u32, d2: f32, q: u32) -> bool {
    return d2 < best_d[k] || (d2 == best_d[k] && q < best_q[k]);
}

// Inserts q at squared distance d2 among the nearest (the farther ones move out by one).
fn consider(q: u32, d2: f32) {
    if (best_n == MAX_BRIDGES && !closer(MAX_BRIDGES - 1u, d2, q)) {
        return;
    }
    var k = min(best_n, MAX_BRIDGES - 1u);
    while (k > 0u && closer(k - 1u, d2, q)) {
        best_d[k] = best_d[k - 1u];
        best_q[k] = best_q[k - 1u];
        k--;
    }
    best_d[k] = d2;
    best_q[k] = q;
    best_n = min(best_n + 1u, MAX_BRIDGES);
}

// The points of cell c within the bridge length of x on strands other than `own`.
fn visit(c: vec3<i32>, x: vec3<f32>, own: u32) {
    let b = bucket_of(c);
    let r2 = P.bridge_length * P.bridge_length;
    for (var s = bucket[b]; s < bucket[b + 1u]; s++) {
        let q = bucket[B_ENTRIES + s];
        let y = state[q].x.xyz;
        let d = y - x;
        let d2 = dot(d, d);
        if (d2 < r2 && all(bridge_cell(y) == c) && points[q].first != own) {
            consider(q, d2);
        }
    }
}

// Pass hair_grid, part 4a: takes the list of searching points for bridge_search (its length,
// and a dispatch of its size, groups() in buffers.rs), and zeroes its count for the next build.
@compute @workgroup_size(1)
fn bridge_search_setup() {
    let n = atomicLoad(&bucket_count[SEARCH_LISTED]);
    atomicStore(&bucket_count[SEARCH_LISTED], 0u);
    bucket[B_SEARCHES] = n;
    let g = max((n + WG - 1u) / WG, 1u);
    if (g <= MAX_GROUPS_X) {
        search_dispatch = array<u32, 3>(g, 1u, 1u);
    } else {
        search_dispatch = array<u32, 3>(MAX_GROUPS_X, (g + MAX_GROUPS_X - 1u) / MAX_GROUPS_X, 1u);
    }
}

// Pass hair_grid, part 4b: each listed point (this turn's, and every wet point with no
// neighbour that has searched since it became wet) finds its MAX_BRIDGES nearest wet points of other strands within the bridge
// length, as HashGrid::for_each_near_by visits them: the own cell first, then the cells whose
// nearest face is not beyond the farthest kept. Written in index order. A thread per listed
// point, so every lane of a subgroup searches (dispatched over all points, seven lanes in
// eight sat idle).
@compute @workgroup_size(WG)
fn bridge_search(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                 @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= bucket[B_SEARCHES]) {
        return;
    }
    let i = bucket[B_SEARCH_LIST + k];
    let at = i * BR_WORDS;
    best_n = 0u;
    for (var k = 0u; k < MAX_BRIDGES; k++) {
        best_d[k] = FAR;
        best_q[k] = 0u;
    }
    let x = state[i].x.xyz;
    let own = points[i].first;
    let r = P.bridge_length;
    let c0 = bridge_cell(x);
    visit(c0, x, own);
    let q = x * (1.0 / r);
    let lo = bridge_cell(x - vec3<f32>(r));
    let hi = bridge_cell(x + vec3<f32>(r));
    // Loops that stop at their last cell: a saturated coordinate never wraps.
    for (var cx = lo.x; ; cx++) {
        for (var cy = lo.y; ; cy++) {
            for (var cz = lo.z; ; cz++) {
                let c = vec3<i32>(cx, cy, cz);
                let cf = vec3<f32>(c);
                let gap = max(max(cf - q, q - (cf + vec3<f32>(1.0))), vec3<f32>(0.0));
                if (any(c != c0) && dot(gap, gap) * r * r * 0.999 <= best_d[MAX_BRIDGES - 1u]) {
                    visit(c, x, own);
                }
                if (cz >= hi.z) {
                    break;
                }
            }
            if (cy >= hi.y) {
                break;
            }
        }
        if (cx >= hi.x) {
            break;
        }
    }
    // Index order (a handful: insertion sort).
    for (var k = 1u; k < best_n; k++) {
        let v = best_q[k];
        var m = k;
        while (m > 0u && best_q[m - 1u] > v) {
            best_q[m] = best_q[m - 1u];
            m--;
        }
        best_q[m] = v;
    }
    for (var k = 0u; k < MAX_BRIDGES; k++) {
        bridge[at + BR_NEAREST + k] = best_q[k];
    }
    bridge[at + BR_COUNT] = best_n;
    bridge[flag_at(i)] = FLAG_SEARCHED;
}

// Pass hair_grid, part 5: the pairs each among the other's nearest (both wet: a point that is
// not wet has no nearest).
@compute @workgroup_size(WG)
fn bridge_pairs(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || !taking_part(i)) {
        return;
    }
    let at = i * BR_WORDS;
    var mask = 0u;
    for (var k = 0u; k < bridge[at + BR_COUNT]; k++) {
        let bq = bridge[at + BR_NEAREST + k] * BR_WORDS;
        for (var m = 0u; m < bridge[bq + BR_COUNT]; m++) {
            if (bridge[bq + BR_NEAREST + m] == i) {
                mask |= 1u << k;
                break;
            }
        }
    }
    bridge[P.bridge_masks + i] = mask;
}

// Each point's length of hair, m: half of each adjacent segment at rest (rest_segments.wgsl).
fn hair_length(i: u32) -> f32 {
    return 0.5 * rest_around(i);
}

// What stiffness a point may still take: a quarter of what an explicit substep holds stably,
// shared among its bridges, m / (4 h^2 n).
fn bridge_room(i: u32) -> f32 {
    let n = max(countOneBits(bridge[P.bridge_masks + i]), 1u);
    return 1.0 / (points[i].inv_mass * 4.0 * P.h * P.h * f32(n));
}

// wet::bridge_stiffness: 4 kappa l min(s_i, s_j) / d_b.
fn bridge_stiffness(len: f32, s_i: f32, s_j: f32) -> f32 {
    if (P.bridge_length <= 0.0) {
        return 0.0;
    }
    return 4.0 * P.bridge_tension * len * clamp(min(s_i, s_j), 0.0, 1.0) / P.bridge_length;
}

// Pass hair_grid, part 6: each bridge's coefficient, the stiffness capped by both points' room
// (the same for both directions).
@compute @workgroup_size(WG)
fn bridge_coef(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
               @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || !taking_part(i)) {
        return;
    }
    let at = i * BR_WORDS;
    let mask = bridge[P.bridge_masks + i];
    let room = bridge_room(i);
    let s_i = min(saturation(held[i], capacity[i]), 1.0);
    let l_i = hair_length(i);
    for (var k = 0u; k < MAX_BRIDGES; k++) {
        if ((mask & (1u << k)) == 0u) {
            continue;
        }
        let j = bridge[at + BR_NEAREST + k];
        let l = 0.5 * (l_i + hair_length(j));
        let stiff = bridge_stiffness(l, s_i, min(saturation(held[j], capacity[j]), 1.0));
        bridge[at + BR_COEF + k] = bitcast<u32>(min(stiff, min(room, bridge_room(j))));
    }
}
