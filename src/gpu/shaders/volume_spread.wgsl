// Pass volume, spreading (cpu/volume.rs): every free point adds its dry mass and its momentum
// to the eight samples around it by integer atomics (`spread_mass`, `spread`, `share`).
//
// A workgroup's points are neighbours along a few strands and share most of their samples, so
// they first sum into a small table in workgroup memory (keyed by sample, open addressing),
// and each sample the workgroup touched then takes one global add per word instead of one per
// point and corner: global atomics on a few hot samples were the pass's whole cost. The sums
// are integers, so the result is the same bits whichever way they are grouped.

@group(0) @binding(3) var<storage, read_write> volume_grid: array<atomic<u32>>;

// Table slots (a power of two): 64 points touch 512 corners, most of them shared.
const SPREAD_SLOTS: u32 = 256u;
const SPREAD_EMPTY: u32 = 0xffffffffu;
// Probes before a corner goes straight to the global grid (a full table: a scattered groom).
const SPREAD_PROBES: u32 = 16u;

var<workgroup> spread_key: array<atomic<u32>, SPREAD_SLOTS>;
var<workgroup> spread_sum: array<atomic<u32>, 2048>; // SPREAD_SLOTS * VOLUME_WORDS

// Adds a word pair to the grid, the carry out of the low word into the high one; adding 0
// changes nothing, so it is skipped (most high words are 0, or all ones cancelled by a carry).
fn volume_add(at: u32, v: vec2<u32>) {
    if (v.x == 0u && v.y == 0u) {
        return;
    }
    let old = atomicAdd(&volume_grid[at], v.x);
    let hi = carried_high(old, v);
    if (hi != 0u) {
        atomicAdd(&volume_grid[at + 1u], hi);
    }
}

// The same into table slot word `at`.
fn spread_add(at: u32, v: vec2<u32>) {
    let old = atomicAdd(&spread_sum[at], v.x);
    let hi = carried_high(old, v);
    if (hi != 0u) {
        atomicAdd(&spread_sum[at + 1u], hi);
    }
}

// The table slot of sample `c` (claimed if new), or SPREAD_EMPTY when the probes run out.
fn spread_slot(c: u32) -> u32 {
    // Fibonacci hashing: the top 8 bits (log2 SPREAD_SLOTS) of c times 2^32 over phi.
    var s = (c * 2654435761u) >> 24u;
    for (var p = 0u; p < SPREAD_PROBES; p++) {
        loop {
            let r = atomicCompareExchangeWeak(&spread_key[s], SPREAD_EMPTY, c);
            if (r.exchanged || r.old_value == c) {
                return s;
            }
            if (r.old_value != SPREAD_EMPTY) {
                break;
            }
            // A weak exchange may fail with the slot still empty: try it again.
        }
        s = (s + 1u) & (SPREAD_SLOTS - 1u);
    }
    return SPREAD_EMPTY;
}

@compute @workgroup_size(WG)
fn volume_spread(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                 @builtin(local_invocation_index) lid: u32) {
    for (var s = lid; s < SPREAD_SLOTS; s += WG) {
        atomicStore(&spread_key[s], SPREAD_EMPTY);
        for (var w = 0u; w < VOLUME_WORDS; w++) {
            atomicStore(&spread_sum[s * VOLUME_WORDS + w], 0u);
        }
    }
    workgroupBarrier();
    let i = linear_id(wid, nwg, lid);
    var f = vec3<f32>(0.0);
    let at = volume_point(i, &f);
    // No early return: every invocation reaches the barriers.
    if (at.y != 0u) {
        let st = state[i];
        let mass = spread_mass(1.0 / points[i].inv_mass, st.x.w);
        let v = clamp(st.v.xyz, vec3<f32>(-MAX_SPREAD_SPEED), vec3<f32>(MAX_SPREAD_SPEED));
        for (var k = 0u; k < 8u; k++) {
            let m = mass * volume_weight(f, k);
            let c = volume_corner(at.x, k);
            let q = array<vec2<u32>, 4>(volume_quanta(m), volume_quanta(m * v.x), volume_quanta(m * v.y),
                                        volume_quanta(m * v.z));
            let s = spread_slot(c);
            for (var w = 0u; w < 4u; w++) {
                if (s == SPREAD_EMPTY) {
                    volume_add(c * VOLUME_WORDS + 2u * w, q[w]);
                } else {
                    spread_add(s * VOLUME_WORDS + 2u * w, q[w]);
                }
            }
        }
    }
    workgroupBarrier();
    for (var s = lid; s < SPREAD_SLOTS; s += WG) {
        let c = atomicLoad(&spread_key[s]);
        if (c != SPREAD_EMPTY) {
            for (var w = 0u; w < 4u; w++) {
                let a = s * VOLUME_WORDS + 2u * w;
                volume_add(c * VOLUME_WORDS + 2u * w,
                           vec2<u32>(atomicLoad(&spread_sum[a]), atomicLoad(&spread_sum[a + 1u])));
            }
        }
    }
}
