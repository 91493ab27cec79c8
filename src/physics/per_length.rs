//! Coefficients quoted per length of hair rather than per point (docs/METHOD.md §1): the air
//! drag on hair points, `c_i (w - v)`, and eq. 2's pull, `s_i g(d)`.
//!
//! The paper gives every point the same `c` and the same `s`, and so does a host that sets the
//! length they are quoted over to 0. A point stands for more or less hair as a groom is
//! sampled more or less finely, so a metre of such hair feels a drag and a pull in proportion
//! to its point count while its weight (masses from a linear density) stays the same: a groom
//! resampled twice as finely swung in a wind as if the air were twice as thick, and a drop
//! pulled it twice as hard. Quoted over a length `L` of hair, point `i` takes `c ℓ_i / L`,
//! `ℓ_i` half of each rest segment it ends, so a strand feels `c / L` per metre however it is
//! sampled; at the paper scene's 2 cm segments and `L` = 2 cm its inner points take `c` as
//! before (to the rounding of `(ℓ + ℓ) c / 2L`), its roots and tips half.

use super::lanes::{rest_segments, Lane, ParamRow, W};

/// The length of hair the air drag and eq. 2's pull are quoted over by default, m: the paper
/// scene's segment, so that scene's inner points keep what they had when both were per point.
pub const DEFAULT_LENGTH: f32 = 0.02;

/// The largest length accepted, m.
pub const MAX_LENGTH: f32 = 1.0;

/// Checks a length a coefficient is quoted over: finite, in `[0, MAX_LENGTH]` (0: per point).
pub(crate) fn check_length(name: &str, v: f32) -> crate::Result<()> {
    if v.is_finite() && (0.0..=MAX_LENGTH).contains(&v) {
        Ok(())
    } else {
        Err(crate::error::invalid!("{name} must be in [0, {MAX_LENGTH}] m, got {v}"))
    }
}

/// A coefficient each hair point takes: the same on every point, or in proportion to the hair
/// it stands for.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerLength {
    /// The coefficient on every point (`scale` 0).
    pub per_point: f32,
    /// The coefficient over `2 L`: a point's per metre of its two rest segments summed; 0:
    /// `per_point` instead.
    pub scale: f32,
}

impl PerLength {
    /// `value` quoted over `length` m of hair (0: on every point as given).
    pub fn new(value: f32, length: f32) -> Self {
        if length > 0.0 {
            PerLength {
                per_point: 0.0,
                scale: value * 0.5 / length,
            }
        } else {
            PerLength {
                per_point: value,
                scale: 0.0,
            }
        }
    }

    /// Whether the coefficient depends on the hair a point stands for.
    #[inline(always)]
    pub fn per_length(&self) -> bool {
        self.scale > 0.0
    }

    /// Whether every point takes 0.
    pub fn is_zero(&self) -> bool {
        self.per_point == 0.0 && self.scale == 0.0
    }

    /// The coefficient of a point whose rest segments are `before` and `after` m long (0 where
    /// the strand has none): `(before + after) value / (2 L)`, or `value`.
    #[inline(always)]
    pub fn at(&self, before: f32, after: f32) -> f32 {
        if self.per_length() {
            (before + after) * self.scale
        } else {
            self.per_point
        }
    }

    /// [`PerLength::at`] for row `i` of a block's rows ([`rest_segments`]), eight lanes at
    /// once.
    #[inline(always)]
    pub fn row(&self, rows: &[ParamRow], i: usize) -> Lane {
        if !self.per_length() {
            return [self.per_point; W];
        }
        std::array::from_fn(|l| {
            let (before, after) = rest_segments(rows, i, l);
            self.at(before, after)
        })
    }
}
