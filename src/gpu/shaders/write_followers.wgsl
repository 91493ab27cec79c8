// Pass write_followers (cpu/followers.rs write_followers; the law is physics/follow.rs,
// function by function): every host vertex from the guide points pass guide_frames made, one
// invocation per vertex. A guide follows itself with weight 1 and a zero offset, which gives
// its own points exactly. With skinned roots each strand is then moved onto its own root
// (physics/follow_roots.rs). Nothing is written once a step has failed, so no NaN reaches the
// vertex buffer.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<uniform> F: FollowUniform;
@group(0) @binding(2) var<storage, read> status: array<u32, 4>;
@group(0) @binding(3) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(4) var<storage, read> follow_strands: array<FollowStrand>;
@group(0) @binding(5) var<storage, read> follow_rest: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read> guide_spans: array<vec4<u32>>;
@group(0) @binding(7) var<storage, read> guide_points: array<vec4<f32>>;
// Skinned roots only (F.roots): per host strand [2h] its root's position, [2h + 1] rotation.
@group(0) @binding(8) var<storage, read> follow_roots: array<vec4<f32>>;

struct FromGuide {
    point: vec3<f32>,
    offset: vec3<f32>,
    wet: f32,
}

// physics/follow.rs from_guide.
fn from_guide(g: u32, i: u32, n: u32, rest_i: vec3<f32>) -> FromGuide {
    let span = guide_spans[g];
    let m = span.z;
    if (m == n) {
        // Point for point: s = i (physics/follow.rs from_guide).
        let p = 3u * (span.x + i);
        let x = guide_points[p];
        return FromGuide(x.xyz, rotate(guide_points[p + 1u], rest_i - guide_points[p + 2u].xyz), x.w);
    }
    let s = f32(i * (m - 1u)) / f32(max(n - 1u, 1u));
    let j = min(u32(s), m - 2u);
    let u = s - f32(j);
    let p0 = 3u * (span.x + j);
    let a = guide_points[p0];
    let b = guide_points[p0 + 3u];
    let r0 = guide_points[p0 + 2u].xyz;
    let r1 = guide_points[p0 + 5u].xyz;
    var frame = guide_points[p0 + 1u];
    if (u > 0.0) {
        frame = guide_points[p0 + 4u];
    }
    let offset = rotate(frame, rest_i - mix3(r0, r1, u));
    return FromGuide(mix3(a.xyz, b.xyz, u), offset, a.w * (1.0 - u) + b.w * u);
}

// physics/follow.rs follow_point: xyz the position, w the wetness.
fn follow_point(guides: vec4<u32>, weights: vec4<f32>, i: u32, n: u32, rest_i: vec3<f32>) -> vec4<f32> {
    let g0 = from_guide(guides.x, i, n, rest_i);
    let shift = F.clump * g0.wet;
    let w0 = weights.x + shift * (1.0 - weights.x);
    var x = (g0.point + g0.offset * (1.0 - F.clump * g0.wet)) * w0;
    var wet = g0.wet * w0;
    for (var k = 1u; k < 3u; k++) {
        if (weights[k] == 0.0) {
            continue;
        }
        let r = from_guide(guides[k], i, n, rest_i);
        let w = weights[k] * (1.0 - shift);
        x += (r.point + r.offset * (1.0 - F.clump * r.wet)) * w;
        wet += r.wet * w;
    }
    return vec4<f32>(x, wet);
}

// physics/follow.rs output_point: point i of host strand h as the output shows it.
fn output_point(h: u32, i: u32) -> vec4<f32> {
    let fs = follow_strands[h];
    let rest_i = follow_rest[fs.first + i].xyz;
    let now = follow_point(fs.guides, fs.weights, i, fs.count, rest_i);
    if (F.blend >= 1.0 || F.has_from == 0u) {
        return now;
    }
    let old = follow_point(fs.from_guides, fs.from_weights, i, fs.count, rest_i);
    return vec4<f32>(mix3(old.xyz, now.xyz, F.blend), old.w * (1.0 - F.blend) + now.w * F.blend);
}

// physics/follow_roots.rs OwnRoot::place: rest point rest_i of host strand h on its frame.
fn own_root_place(h: u32, rest_i: vec3<f32>) -> vec3<f32> {
    let fs = follow_strands[h];
    let r0 = follow_rest[fs.first].xyz;
    return follow_roots[2u * h].xyz + quat_rotate(follow_roots[2u * h + 1u], rest_i - r0);
}

// physics/follow_roots.rs OwnRoot::shift: the law's last root point onto the frame.
fn own_root_shift(h: u32) -> vec3<f32> {
    let fs = follow_strands[h];
    let last = fs.root_points - 1u;
    return own_root_place(h, follow_rest[fs.first + last].xyz) - output_point(h, last).xyz;
}

// physics/follow_roots.rs OwnRoot::point: point i of host strand h (where the law put it,
// law_i) on its own root.
fn own_root_point(h: u32, i: u32, law_i: vec3<f32>, shift: vec3<f32>) -> vec3<f32> {
    let fs = follow_strands[h];
    let k = fs.root_points;
    if (i < k) {
        return own_root_place(h, follow_rest[fs.first + i].xyz);
    }
    let u = f32(fs.count - 1u - i) / f32(fs.count - k);
    return law_i + shift * (u * u);
}

@compute @workgroup_size(WG)
fn write_followers(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>,
                   @builtin(local_invocation_index) lid: u32) {
    let v = linear_id(wid, nwg, lid);
    if (v >= F.host_points || status[STATUS_FLAGS] != 0u) {
        return;
    }
    let h = bitcast<u32>(follow_rest[v].w);
    let fs = follow_strands[h];
    let i = v - fs.first;
    var here = output_point(h, i);
    // physics/follow.rs tangent: from the neighbours (this point at the ends).
    var a = here.xyz;
    var b = here.xyz;
    if (P.tan_off != NO_ATTRIBUTE) {
        if (i > 0u) {
            a = output_point(h, i - 1u).xyz;
        }
        if (i + 1u < fs.count) {
            b = output_point(h, i + 1u).xyz;
        }
    }
    if (F.roots != 0u && fs.root_points > 0u) {
        // physics/follow_roots.rs root_strand: every point of the strand moved alike.
        let shift = own_root_shift(h);
        let moved = own_root_point(h, i, here.xyz, shift);
        here = vec4<f32>(moved, here.w);
        // The neighbours (the law's, read above) as moved; this point at the ends, as before.
        if (P.tan_off != NO_ATTRIBUTE && i > 0u) {
            a = own_root_point(h, i - 1u, a, shift);
        } else {
            a = moved;
        }
        if (P.tan_off != NO_ATTRIBUTE && i + 1u < fs.count) {
            b = own_root_point(h, i + 1u, b, shift);
        } else {
            b = moved;
        }
    }
    write_vertex(v, here.xyz, a, b, here.w);
}
