// Pass write_followers (cpu/followers.rs; the law is physics/followers.rs, function by
// function): every host vertex from the simulated guides, one invocation per vertex. A guide
// follows itself with weight 1 and a zero offset, which gives its own points exactly. Nothing
// is written once a step has failed, so no NaN reaches the vertex buffer. Bound only in
// scenes with guides.

@group(0) @binding(0) var<uniform> P: Params;
@group(0) @binding(1) var<uniform> F: FollowUniform;
@group(0) @binding(2) var<storage, read> state: array<State>;
@group(0) @binding(3) var<storage, read> status: array<u32, 4>;
@group(0) @binding(4) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(5) var<storage, read> follow_strands: array<FollowStrand>;
@group(0) @binding(6) var<storage, read> follow_rest: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read> guide_spans: array<vec4<u32>>;
@group(0) @binding(8) var<storage, read> output_from: array<State>;

// Guide g's point j: its position (moved from the kept one when the fixed steps' output
// blends) and wetness.
fn guide_at(g: u32, j: u32) -> vec4<f32> {
    let k = guide_spans[g].x + j;
    let x = state[k].x;
    if (F.kept != 0u) {
        let p = output_from[k].x.xyz;
        return vec4<f32>(p + F.kept_a * (x.xyz - p), x.w);
    }
    return x;
}

// physics/followers.rs mix.
fn mix3(a: vec3<f32>, b: vec3<f32>, u: f32) -> vec3<f32> {
    return a * (1.0 - u) + b * u;
}

// physics/followers.rs turn.
fn turn(v: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let k = cross(a, b);
    let c = dot(a, b);
    if (1.0 + c < TURN_EPS) {
        return v;
    }
    return v * c + cross(k, v) + k * (dot(k, v) / (1.0 + c));
}

// physics/followers.rs unit: d over its length, or zero when that is zero or not finite.
fn unit_or_zero(d: vec3<f32>) -> vec3<f32> {
    let len2 = dot(d, d);
    if (len2 > 0.0 && !non_finite(len2)) {
        return d * (1.0 / sqrt(len2));
    }
    return vec3<f32>(0.0);
}

// physics/followers.rs: the head's rotation (a unit quaternion) applied to v.
fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

struct FromGuide {
    point: vec3<f32>,
    offset: vec3<f32>,
    wet: f32,
}

// physics/followers.rs from_guide.
fn from_guide(g: u32, i: u32, n: u32, rest_i: vec3<f32>) -> FromGuide {
    let span = guide_spans[g];
    let m = span.z;
    let s = f32(i * (m - 1u)) / f32(max(n - 1u, 1u));
    let j = min(u32(s), m - 2u);
    let u = s - f32(j);
    let a = guide_at(g, j);
    let b = guide_at(g, j + 1u);
    let r0 = follow_rest[span.y + j].xyz;
    let r1 = follow_rest[span.y + j + 1u].xyz;
    let offset = rotate(F.head, rest_i - mix3(r0, r1, u));
    // The segment arriving at s: j's own inside it, the one before at a point; none at the
    // root, whose offset turns with the head alone.
    var turned = offset;
    if (u > 0.0 || j > 0u) {
        var k = j;
        var a1 = a.xyz;
        var b1 = b.xyz;
        if (u <= 0.0) {
            k = j - 1u;
            a1 = guide_at(g, k).xyz;
            b1 = a.xyz;
        }
        let ta = unit_or_zero(rotate(F.head, follow_rest[span.y + k + 1u].xyz - follow_rest[span.y + k].xyz));
        let tb = unit_or_zero(b1 - a1);
        if (any(ta != vec3<f32>(0.0)) && any(tb != vec3<f32>(0.0))) {
            turned = turn(offset, ta, tb);
        }
    }
    return FromGuide(mix3(a.xyz, b.xyz, u), turned, a.w * (1.0 - u) + b.w * u);
}

// physics/followers.rs follow_point: xyz the position, w the wetness.
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

// physics/followers.rs output_point: point i of host strand h as the output shows it.
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
    let here = output_point(h, i);
    let o = v * P.stride;
    if (P.pos_off != NO_ATTRIBUTE) {
        vertices[o + P.pos_off] = here.x;
        vertices[o + P.pos_off + 1u] = here.y;
        vertices[o + P.pos_off + 2u] = here.z;
    }
    if (P.tan_off != NO_ATTRIBUTE) {
        // physics/followers.rs tangent: from the neighbours (this point at the ends).
        var a = here.xyz;
        var b = here.xyz;
        if (i > 0u) {
            a = output_point(h, i - 1u).xyz;
        }
        if (i + 1u < fs.count) {
            b = output_point(h, i + 1u).xyz;
        }
        var t = unit_or_zero(b - a);
        if (all(t == vec3<f32>(0.0))) {
            t = vec3<f32>(0.0, 0.0, 1.0);
        }
        vertices[o + P.tan_off] = t.x;
        vertices[o + P.tan_off + 1u] = t.y;
        vertices[o + P.tan_off + 2u] = t.z;
    }
    if (P.wet_off != NO_ATTRIBUTE) {
        vertices[o + P.wet_off] = here.w;
    }
}
