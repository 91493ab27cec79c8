// A root frame's rotation of a vector (physics/roots.rs `RootFrame::place`, glam's
// `Quat * Vec3`), shared by the pinning pass (roots.wgsl) and the followers' own roots
// (write_followers.wgsl), so that both place a point with the same operations.

// q v q* (glam's `Quat * Vec3`).
fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = q.xyz;
    let b2 = dot(b, b);
    return v * (q.w * q.w - b2) + b * (dot(v, b) * 2.0) + cross(b, v) * (q.w * 2.0);
}
