// A workgroup's inclusive prefix sum, and the exclusive one of a counting sort's block sums,
// shared by the modules that sort by counting (the water grid, the liquid bridges' hashed
// grid, the records of the particles' gather; counting_scan.wgsl has the per-block parts) and
// the held water's drips. Each of them defines `block_sum(k)` and `set_block_sum(k, v)` over
// its own buffer.

var<workgroup> scan: array<u32, 256>;

// Inclusive prefix sum of one value per invocation over the workgroup (Hillis-Steele) into
// `scan`; every invocation of the workgroup must call it.
fn scan_inclusive(lid: u32, v: u32) {
    scan[lid] = v;
    workgroupBarrier();
    for (var off = 1u; off < 256u; off <<= 1u) {
        var add = 0u;
        if (lid >= off) {
            add = scan[lid - off];
        }
        workgroupBarrier();
        scan[lid] += add;
        workgroupBarrier();
    }
}

// Exclusive prefix sum of `blocks` block sums in place, by one workgroup of 256, each
// invocation over a run of blocks; returns the total. Every invocation must call it.
fn scan_block_sums(lid: u32, blocks: u32) -> u32 {
    let chunk = (blocks + 255u) / 256u;
    let a = min(lid * chunk, blocks);
    let b = min(a + chunk, blocks);
    var sum = 0u;
    for (var k = a; k < b; k++) {
        sum += block_sum(k);
    }
    scan_inclusive(lid, sum);
    var run = scan[lid] - sum;
    for (var k = a; k < b; k++) {
        let t = block_sum(k);
        set_block_sum(k, run);
        run += t;
    }
    return scan[255];
}
