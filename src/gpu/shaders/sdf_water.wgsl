// Pass water_integrate, SDF part (cpu/water.rs `integrate`: after the analytic colliders):
// every particle water_integrate just moved, in grid order.

@group(0) @binding(3) var<storage, read_write> sorted: array<Particle>;
@group(0) @binding(4) var<storage, read> grid: array<u32>;

@compute @workgroup_size(WG)
fn water_sdf(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
             @builtin(local_invocation_index) lid: u32) {
    let k = linear_id(wid, nwg, lid);
    if (k >= grid[G_COUNT]) {
        return;
    }
    var p = sorted[k];
    var x = p.x;
    var v = p.v;
    for (var j = 0u; j < NSDF; j++) {
        collide_sdf(&x, &v, SS.sdfs[j], P.friction);
    }
    p.x = x;
    p.v = v;
    sorted[k] = p;
}
