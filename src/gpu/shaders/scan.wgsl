// A workgroup's inclusive prefix sum, shared by the modules that sort by counting (the water
// grid and the liquid bridges' hashed grid).

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
