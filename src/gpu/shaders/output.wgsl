// Pass write_vertices (cpu/output.rs): the attributes the host asked for, interleaved, in the
// host's strand order. Nothing is written once a step has failed, so no NaN reaches the
// vertex buffer. write_vertices_blended writes the positions kept before the last step moved
// toward the current ones (fixed steps with interpolation: sim/fixed.rs); its two bindings
// exist only once a simulation blends.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<storage, read> points: array<Point>;
@group(0) @binding(2) var<storage, read> state: array<State>;
@group(0) @binding(3) var<storage, read> status: array<u32, 4>;
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(5) var<storage, read> output_from: array<State>;
@group(0) @binding(6) var<uniform> B: Blend;

// The point this invocation writes, or none (past the end, or after a failed step).
fn vertex_index(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    let i = linear_id(wid, nwg, lid);
    if (i >= P.points || status[STATUS_FLAGS] != 0u) {
        return NO_ATTRIBUTE;
    }
    return i;
}

// The points before and after i along its strand (i itself at the ends) for the tangent;
// i twice when no tangent is asked for.
fn neighbours(i: u32) -> vec2<u32> {
    if (P.tan_off == NO_ATTRIBUTE) {
        return vec2<u32>(i, i);
    }
    let pt = points[i];
    return vec2<u32>(max(i, pt.first + 1u) - 1u, min(i + 1u, pt.last));
}

@compute @workgroup_size(WG)
fn write_vertices(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                  @builtin(local_invocation_index) lid: u32) {
    let i = vertex_index(wid, nwg, lid);
    if (i == NO_ATTRIBUTE) {
        return;
    }
    let n = neighbours(i);
    let x = state[i].x;
    write_vertex(i, x.xyz, state[n.x].x.xyz, state[n.y].x.xyz, x.w);
}

// The output blend (L3::toward): p moved toward x by B.a.
fn toward(p: vec3<f32>, x: vec3<f32>) -> vec3<f32> {
    return p + B.a * (x - p);
}

// Point j's blended position.
fn blended(j: u32) -> vec3<f32> {
    return toward(output_from[j].x.xyz, state[j].x.xyz);
}

@compute @workgroup_size(WG)
fn write_vertices_blended(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                          @builtin(local_invocation_index) lid: u32) {
    let i = vertex_index(wid, nwg, lid);
    if (i == NO_ATTRIBUTE) {
        return;
    }
    let n = neighbours(i);
    write_vertex(i, blended(i), blended(n.x), blended(n.y), state[i].x.w);
}
