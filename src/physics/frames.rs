//! The frames the host places colliders by, each step (SDF colliders, and analytic colliders
//! on bones of their own): a rotation, a translation and a uniform scale, so that a distance
//! in the collider's frame scales by one number into the world. Checked once here for both.

use crate::error::{invalid, Result};
use glam::Affine3A;

/// How far a transform's scale may differ between axes (relative): distances scale by one
/// number, so the transform must be a rotation, a translation and a uniform scale.
pub const UNIFORM_SCALE_TOLERANCE: f32 = 1e-3;

/// The affine transform of a column-major 4×4 matrix `m`, refused unless its last row is
/// (0, 0, 0, 1) and [`check_transform`] accepts it.
pub fn transform_from_mat4(m: glam::Mat4, name: &str) -> Result<Affine3A> {
    let row3 = m.row(3);
    if !row3.is_finite() || (row3 - glam::Vec4::W).abs().max_element() > 1e-5 {
        return Err(invalid!(
            "{name}: transform's last row must be (0, 0, 0, 1), got {row3:?}"
        ));
    }
    let t = Affine3A::from_mat4(m);
    check_transform(&t, name)?;
    Ok(t)
}

/// Refuses a transform that is not finite, not affine with a positive determinant, or that
/// scales its axes differently (distances then would not scale by one number).
pub fn check_transform(t: &Affine3A, name: &str) -> Result<()> {
    let m = glam::Mat4::from(*t).to_cols_array();
    if m.iter().any(|v| !v.is_finite()) {
        return Err(invalid!("{name}: transform has a non-finite entry"));
    }
    let det = t.matrix3.determinant();
    if det.is_nan() || det <= 1e-12 {
        return Err(invalid!(
            "{name}: transform is singular or mirrored (determinant {det})"
        ));
    }
    let s = det.cbrt();
    for (a, c) in ["x", "y", "z"]
        .iter()
        .zip([t.matrix3.x_axis, t.matrix3.y_axis, t.matrix3.z_axis])
    {
        if (c.length() / s - 1.0).abs() > UNIFORM_SCALE_TOLERANCE {
            return Err(invalid!(
                "{name}: transform must be a rotation, translation and uniform scale ({a} axis scaled {} against {s})",
                c.length()
            ));
        }
    }
    Ok(())
}
