//! Trilinear interpolation of a value sampled at a cell's eight corners, with its gradient:
//! the SDF colliders read their distance through it and hair-hair volume its density.
//! `common.wgsl` `trilinear` mirrors it.

use glam::Vec3;

/// The value at fractions `f` of the cell whose corner values are `c` (x fastest), and its
/// gradient per cell (divide by the cell for per metre): along x on the four edges, then y,
/// then z, the gradient from the same edges.
#[inline]
pub fn trilinear(c: &[f32; 8], f: Vec3) -> (f32, Vec3) {
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(c[0], c[1], f.x);
    let x10 = lerp(c[2], c[3], f.x);
    let x01 = lerp(c[4], c[5], f.x);
    let x11 = lerp(c[6], c[7], f.x);
    let y0 = lerp(x00, x10, f.y);
    let y1 = lerp(x01, x11, f.y);
    let d = lerp(y0, y1, f.z);
    let dx = lerp(
        lerp(c[1] - c[0], c[3] - c[2], f.y),
        lerp(c[5] - c[4], c[7] - c[6], f.y),
        f.z,
    );
    let dy = lerp(x10 - x00, x11 - x01, f.z);
    let dz = y1 - y0;
    (d, Vec3::new(dx, dy, dz))
}
