// The vertex output's one writer (output.wgsl and write_followers.wgsl both call it): the
// attributes the host asked for, interleaved, at vertex i. The module declares `P` and
// `vertices`.

// Writes vertex i from its position x, its strand neighbours' positions a (before) and b
// (after), and its wetness.
fn write_vertex(i: u32, x: vec3<f32>, a: vec3<f32>, b: vec3<f32>, wet: f32) {
    let o = i * P.stride;
    if (P.pos_off != NO_ATTRIBUTE) {
        vertices[o + P.pos_off] = x.x;
        vertices[o + P.pos_off + 1u] = x.y;
        vertices[o + P.pos_off + 2u] = x.z;
    }
    if (P.tan_off != NO_ATTRIBUTE) {
        let d = b - a;
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
        vertices[o + P.wet_off] = wet;
    }
}
