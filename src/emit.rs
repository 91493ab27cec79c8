//! Water emitters (docs/WET_MODEL.md §9): rain over a rectangle and a spray cone, so a host
//! need not script particles. Each step, an emitter of rate `R` drops/s adds the drops whose
//! numbers fall in `[floor(R t), floor(R (t + dt)))` on the simulation's own clock, and drop
//! number `k` is a pure function of `(seed, k)`: the same drops on every run, backend and
//! thread count, and a replay from the same clock adds the same water.

use crate::error::{check_finite3, invalid, Result};
use glam::Vec3;

/// Rain: drops appear uniformly over a horizontal rectangle and fall at `speed`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rain {
    /// Centre of the rectangle drops start from, world space, m.
    pub center: Vec3,
    /// The rectangle's extent along x and y, m (each >= 0).
    pub size: [f32; 2],
    /// Drops per second (>= 0; 0 stops the rain).
    pub rate: f32,
    /// Fall speed, m/s, straight down (-z).
    pub speed: f32,
    /// Seed of the drops' places.
    pub seed: u32,
}

/// A spray: drops leave `origin` within `half_angle` of `direction` at `speed`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spray {
    /// Nozzle position, world space, m.
    pub origin: Vec3,
    /// The cone's axis (any length > 0).
    pub direction: Vec3,
    /// The cone's half-angle, radians, in [0, pi].
    pub half_angle: f32,
    /// Drops per second (>= 0).
    pub rate: f32,
    /// Drop speed, m/s.
    pub speed: f32,
    /// Seed of the drops' directions.
    pub seed: u32,
}

/// Either emitter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emitter {
    /// Rain over a rectangle.
    Rain(Rain),
    /// A spray cone.
    Spray(Spray),
}

/// The most drops per second an emitter may add (a million: far above what a frame's
/// particle capacity holds).
pub const MAX_RATE: f32 = 1.0e6;

impl Emitter {
    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<()> {
        let (rate, speed) = match self {
            Emitter::Rain(r) => {
                check_finite3("rain center", r.center.to_array())?;
                if !r.size.iter().all(|s| s.is_finite() && *s >= 0.0) {
                    return Err(invalid!("rain size must be finite and >= 0 m, got {:?}", r.size));
                }
                (r.rate, r.speed)
            }
            Emitter::Spray(s) => {
                check_finite3("spray origin", s.origin.to_array())?;
                check_finite3("spray direction", s.direction.to_array())?;
                if s.direction.length_squared() == 0.0 || !s.direction.length_squared().is_finite() {
                    return Err(invalid!("spray direction must be non-zero, got {}", s.direction));
                }
                if !(s.half_angle.is_finite() && (0.0..=std::f32::consts::PI).contains(&s.half_angle)) {
                    return Err(invalid!(
                        "spray half_angle must be in [0, pi] rad, got {}",
                        s.half_angle
                    ));
                }
                (s.rate, s.speed)
            }
        };
        if !(rate.is_finite() && (0.0..=MAX_RATE).contains(&rate)) {
            return Err(invalid!(
                "emitter rate must be in [0, {MAX_RATE:e}] drops/s, got {rate}"
            ));
        }
        if !(speed.is_finite() && (0.0..=crate::params::Wind::MAX_SPEED).contains(&speed)) {
            return Err(invalid!("emitter speed must be in [0, 100] m/s, got {speed}"));
        }
        Ok(())
    }

    /// The numbers of the drops this emitter adds over `[t, t + dt)`.
    pub fn drops_between(&self, t: f64, dt: f64) -> std::ops::Range<u64> {
        let rate = match self {
            Emitter::Rain(r) => r.rate,
            Emitter::Spray(s) => s.rate,
        } as f64;
        (rate * t).floor() as u64..(rate * (t + dt)).floor() as u64
    }

    /// Drop number `k`: its position and velocity.
    pub fn drop(&self, k: u64) -> (Vec3, Vec3) {
        match self {
            Emitter::Rain(r) => {
                let (u, v) = (unit(r.seed, k, 0), unit(r.seed, k, 1));
                let off = Vec3::new((u - 0.5) * r.size[0], (v - 0.5) * r.size[1], 0.0);
                (r.center + off, Vec3::new(0.0, 0.0, -r.speed))
            }
            Emitter::Spray(s) => {
                // Uniform over the cone's cap: cos(theta) uniform in [cos(half_angle), 1].
                let axis = s.direction.normalize();
                let c = 1.0 - unit(s.seed, k, 0) * (1.0 - s.half_angle.cos());
                let sin = (1.0 - c * c).max(0.0).sqrt();
                let phi = std::f32::consts::TAU * unit(s.seed, k, 1);
                let (b1, b2) = axis.any_orthonormal_pair();
                let dir = axis * c + (b1 * phi.cos() + b2 * phi.sin()) * sin;
                (s.origin, dir * s.speed)
            }
        }
    }
}

/// A number in [0, 1) from `(seed, k, lane)`: a counter-based hash (SplitMix64's finaliser),
/// so drop `k` never depends on the drops before it.
fn unit(seed: u32, k: u64, lane: u64) -> f32 {
    let mut z = (seed as u64) << 32 ^ k.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ lane.wrapping_mul(0xd1b5_4a32_d192_ed03);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}
