// The follower law (physics/follow.rs), function by function; the passes guide_frames
// (guide_frames.wgsl) and write_followers (write_followers.wgsl) call it.

// physics/follow.rs mix.
fn mix3(a: vec3<f32>, b: vec3<f32>, u: f32) -> vec3<f32> {
    return a * (1.0 - u) + b * u;
}

// physics/follow.rs rotate: v turned by the unit quaternion q (xyzw).
fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// physics/follow.rs quat_mul: turn by b, then by a.
fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(b.xyz * a.w + a.xyz * b.w + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

// physics/follow.rs unit: d over its length, or zero when that is zero or not finite.
fn unit_or_zero(d: vec3<f32>) -> vec3<f32> {
    let len2 = dot(d, d);
    if (len2 > 0.0 && !non_finite(len2)) {
        return d * (1.0 / sqrt(len2));
    }
    return vec3<f32>(0.0);
}

// physics/follow.rs guide_frame: the head's rotation, then the smallest rotation from the
// arriving segment's rest direction (rb - ra, turned by the head) to its current one (xb - xa).
fn guide_frame(head: vec4<f32>, ra: vec3<f32>, rb: vec3<f32>, xa: vec3<f32>, xb: vec3<f32>) -> vec4<f32> {
    let a = unit_or_zero(rotate(head, rb - ra));
    let b = unit_or_zero(xb - xa);
    if (all(a == vec3<f32>(0.0)) || all(b == vec3<f32>(0.0))) {
        return head;
    }
    let c = dot(a, b);
    if (1.0 + c < TURN_EPS) {
        return head;
    }
    let q = vec4<f32>(cross(a, b), 1.0 + c);
    return quat_mul(q * (1.0 / sqrt(dot(q, q))), head);
}
