// Pass write_vertices (cpu/output.rs): the attributes the host asked for, interleaved, in the
// host's strand order. Nothing is written once a step has failed, so no NaN reaches the
// vertex buffer.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> points: array<Point>;
@group(0) @binding(2) var<storage, read> state: array<State>;
@group(0) @binding(3) var<storage, read> status: array<u32, 4>;
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;

@compute @workgroup_size(WG)
fn write_vertices(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || status[STATUS_FLAGS] != 0u) {
        return;
    }
    let o = i * P.stride;
    let x = state[i].x;
    if (P.pos_off != NO_ATTRIBUTE) {
        vertices[o + P.pos_off] = x.x;
        vertices[o + P.pos_off + 1u] = x.y;
        vertices[o + P.pos_off + 2u] = x.z;
    }
    if (P.tan_off != NO_ATTRIBUTE) {
        let pt = points[i];
        let d = state[min(i + 1u, pt.last)].x.xyz - state[max(i, pt.first + 1u) - 1u].x.xyz;
        let len = sqrt(dot(d, d));
        var t = vec3<f32>(0.0, 0.0, 1.0);
        if (len > 0.0 && !non_finite(1.0 / len)) {
            t = d * (1.0 / len);
        }
        vertices[o + P.tan_off] = t.x;
        vertices[o + P.tan_off + 1u] = t.y;
        vertices[o + P.tan_off + 2u] = t.z;
    }
    if (P.wet_off != NO_ATTRIBUTE) {
        vertices[o + P.wet_off] = x.w;
    }
}
