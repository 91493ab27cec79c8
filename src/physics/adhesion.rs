//! Eq. 2: a water particle pulls nearby hair points onto its surface shell.
//!
//! `g(d) = 1 - ((2d - r_min - r_max) / (r_min - r_max))²` for `d <= r_max`, else 0; the force
//! on hair point i from particle j is `s g(d) (p_j - p_i)/d`, and particle j gets the opposite.
//! `g` is 0 at `r_min` and `r_max`, 1 halfway, negative (repulsive) inside `r_min`.

use glam::Vec3;

/// Below this distance (m) the direction between a hair point and a particle is undefined;
/// the pair exerts no force (both sides get zero, so momentum is still conserved).
pub const MIN_DISTANCE: f32 = 1.0e-9;

/// Eq. 2's profile `g(d)`.
#[inline(always)]
pub fn profile(d: f32, r_min: f32, r_max: f32) -> f32 {
    if d > r_max {
        return 0.0;
    }
    let u = (2.0 * d - r_min - r_max) / (r_min - r_max);
    1.0 - u * u
}

/// The force on a hair point at `hair` from a particle at `water`, given `d2 = |water-hair|²`.
/// Returns zero beyond `r_max` and below [`MIN_DISTANCE`].
#[inline(always)]
pub fn force_on_hair(hair: Vec3, water: Vec3, d2: f32, r_min: f32, r_max: f32, s: f32) -> Vec3 {
    if d2 > r_max * r_max || d2 < MIN_DISTANCE * MIN_DISTANCE {
        return Vec3::ZERO;
    }
    let d = d2.sqrt();
    (water - hair) * (s * profile(d, r_min, r_max) / d)
}
