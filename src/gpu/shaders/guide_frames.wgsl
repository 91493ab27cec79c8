// Pass guide_frames (cpu/followers.rs guide_frames): each simulated guide point's position,
// wetness and frame (physics/follow.rs guide_frame_at), one invocation per guide, starting
// from the head's rotation, or with skinned roots the guide's own root's. Guides read the kept
// positions moved toward the state while the fixed steps' output blends.

@group(0) @binding(0) var<uniform> F: FollowUniform;
@group(0) @binding(1) var<storage, read> state: array<State>;
@group(0) @binding(2) var<storage, read> output_from: array<State>;
@group(0) @binding(3) var<storage, read> guide_spans: array<vec4<u32>>;
@group(0) @binding(4) var<storage, read> follow_rest: array<vec4<f32>>;
// Per guide point: [3p] position and wetness, [3p + 1] frame, [3p + 2] rest position.
@group(0) @binding(5) var<storage, read_write> guide_points: array<vec4<f32>>;
// Skinned roots only (F.roots): per host strand [2h] its root's position, [2h + 1] rotation.
@group(0) @binding(6) var<storage, read> follow_roots: array<vec4<f32>>;

// Guide-groom point k's position (blended when the fixed steps' output blends) and wetness.
fn guide_x(k: u32) -> vec4<f32> {
    let x = state[k].x;
    if (F.kept != 0u) {
        let p = output_from[k].x.xyz;
        return vec4<f32>(p + F.kept_a * (x.xyz - p), x.w);
    }
    return x;
}

@compute @workgroup_size(WG)
fn guide_frames(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                @builtin(local_invocation_index) lid: u32) {
    let g = linear_id(wid, nwg, lid);
    if (g >= F.guides) {
        return;
    }
    let span = guide_spans[g];
    var start = F.head;
    if (F.roots != 0u) {
        start = follow_roots[2u * span.w + 1u];
    }
    var prev = vec3<f32>(0.0);
    for (var j = 0u; j < span.z; j++) {
        let x = guide_x(span.x + j);
        var frame = start;
        if (j > 0u) {
            frame = guide_frame(start, follow_rest[span.y + j - 1u].xyz, follow_rest[span.y + j].xyz, prev, x.xyz);
        }
        let k = 3u * (span.x + j);
        guide_points[k] = x;
        guide_points[k + 1u] = frame;
        guide_points[k + 2u] = follow_rest[span.y + j];
        prev = x.xyz;
    }
}
