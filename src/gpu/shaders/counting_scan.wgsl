// The prefix sum of a counting sort's bucket counts, in blocks of SCAN_BLOCK buckets, shared
// by the modules that sort by counting: the water grid (water.wgsl), the liquid bridges' hair
// grid (bridges.wgsl) and the records of the particles' gather (reactions.wgsl). Each
// defines, over its own buffers, `count_of(b)`, `start_of(b)` and `set_start(b, v)` for
// bucket b, and scan.wgsl's `block_sum(k)` and `set_block_sum(k, v)`. A sort's scan is
// `scan_counts_block` for each block, `scan_block_totals` in one workgroup, then
// `add_block_offset` for each block.

// Part a, run by the 256 invocations of the workgroup for block `block`: the exclusive prefix
// sum of the counts of its buckets (those below `buckets`) into their starts, and the block's
// total into its block sum.
fn scan_counts_block(block: u32, lid: u32, buckets: u32) {
    let base = block * SCAN_BLOCK + lid * 4u;
    var c = array<u32, 4>(0u, 0u, 0u, 0u);
    var sum = 0u;
    for (var k = 0u; k < 4u; k++) {
        if (base + k < buckets) {
            c[k] = count_of(base + k);
        }
        sum += c[k];
    }
    scan_inclusive(lid, sum);
    var run = scan[lid] - sum;
    for (var k = 0u; k < 4u; k++) {
        if (base + k < buckets) {
            set_start(base + k, run);
        }
        run += c[k];
    }
    if (lid == 255u) {
        set_block_sum(block, scan[255]);
    }
}

// Part b, run by one workgroup of 256: the block sums' exclusive prefix sum (scan.wgsl
// `scan_block_sums`), and their total as the start past the last of the `buckets` buckets.
fn scan_block_totals(lid: u32, buckets: u32) {
    let total = scan_block_sums(lid, (buckets + SCAN_BLOCK - 1u) / SCAN_BLOCK);
    if (lid == 255u) {
        set_start(buckets, total);
    }
}

// Part c: block `block`'s offset (its block sum, once scanned) added to its buckets' starts.
fn add_block_offset(block: u32, lid: u32, buckets: u32) {
    let add = block_sum(block);
    let base = block * SCAN_BLOCK + lid * 4u;
    for (var k = 0u; k < 4u; k++) {
        if (base + k < buckets) {
            set_start(base + k, start_of(base + k) + add);
        }
    }
}
