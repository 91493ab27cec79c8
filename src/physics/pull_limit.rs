//! Eq. 2's stability limit (docs/METHOD.md §2, "The pull's stability limit"): the pull is
//! explicit, and on light hair it is stiffer than a substep can follow.
//!
//! Eq. 2's force `s g(d)` is steepest at its shell's two edges, `|s g'(d)| = 4 s / (r_max −
//! r_min)`: 5.3 N/m a pair with the paper's `s` = 8 mN, `r_min` = 2 mm, `r_max` = 8 mm. A
//! paper-scene point weighs 1 g, and one pair there gives `h² K / m` = 0.09 at a 240 Hz
//! substep. A real groom's point weighs 10 mg (1 g/m, 1 cm segments), and the same pair, even
//! quoted per 2 cm of hair, gives 4.6: past symplectic Euler's bound of 4, and the implicit
//! solves take the pull explicitly too. Particles also pile up where nothing pushes them
//! apart (the paper's model has no particle-particle force): the TressFX ponytail under 1,000
//! drops at 16 substeps had 70 within reach of one point. Such points ring in the drops' wells
//! and tear their segments: the ponytail's longest was 68-113 % past its rest length in the
//! first 10 frames at 4 substeps, and 200 % at 16, against 0.8 % dry.
//!
//! So each hair point's pulls are scaled, per substep, by `min(1, LIMIT / q)`, `q = h² K / m`
//! with `K` the sum of its pairs' stiffnesses (times its share) and `LIMIT` =
//! [`PULL_STIFFNESS_LIMIT`]: a point with `q` within it keeps eq. 2 exactly (the same bits), a
//! stiffer one pulls with the most stiffness the substep follows. A pair's stiffness is its
//! stiffest restoring mode at its distance ([`super::adhesion::pair_stiffness`]: the pull's
//! derivative in the point's position has the same eigenvalues as in the particle's), and by
//! Weyl's inequality their sum bounds the point's stiffest mode under all its pulls at once.
//! The profile's steepest slope, which the sum once took for every pair, counted a pair at
//! the shell's outer edge, where the pull is held by nothing (its slope there lets go), as
//! stiffly as one at the inner edge: on the TressFX ponytail under 1,000 drops of 10 mg it
//! held the tips' clumping at 7.6 mm after 2 s at 4 substeps against 4.4 at 64; with each
//! pair's own stiffness it is 4.9 against 4.1. The pair's two forces take the same factor, so
//! momentum is conserved as before. As `h → 0` the factor goes to 1: more substeps give more
//! of eq. 2, and the f64 reference (`reference.rs`, the limit `h → 0`) has none.
//!
//! A particle is held to the same limit from its side ([`particle_limit`]): drops sit where
//! the hair clumps around them, up to 430 of the paper scene's points within one drop's reach,
//! and their stiffest mode (from the pulls' summed derivative, measured) reached 1.5 times
//! symplectic Euler's bound at the paper's 4 substeps. Such drops rang and were flung out: of
//! 1,000 drops in the paper scene's hair, 360 were left after 60 frames against 736 at 16
//! substeps, and 10 mg drops left at 64 m/s. It sums the same pair stiffnesses as the hair
//! side, from the particle's side of each pair. While it acts the particle's response to its
//! forces, not the forces, takes the factor, so momentum is not conserved then (the hair
//! takes the full pull, the drop a part); where it rests, nothing changes.

use super::adhesion::pair_stiffness;
use super::lanes::{Lane, L3, W};

/// The most `h² K / m` eq. 2 may give a hair point in a substep: a quarter of symplectic
/// Euler's bound of 4, the rest left to the springs (which take up to 3.6 of it where
/// [`crate::Integrator::AUTO`] picks symplectic Euler) and to the bridges' own share.
pub const PULL_STIFFNESS_LIMIT: f32 = 1.0;

/// What a substep `h` and eq. 2's shell make of one newton of pull strength: `h²` times the
/// profile's steepest slope `4 / (r_max − r_min)`, so that a point pulled with strengths
/// summing to `S` and inverse mass `w` has `q = slope_h2 · S · w`.
#[inline]
pub fn slope_h2(h: f32, r_min: f32, r_max: f32) -> f32 {
    h * h * (4.0 / (r_max - r_min))
}

/// The factor on a hair point's pulls: 1 while `q = slope_h2 · stiffness · weight · inv_mass`
/// stays within [`PULL_STIFFNESS_LIMIT`], else `LIMIT / q` (`stiffness`: over the particles
/// within its reach, each one's strength times the pair's
/// [`super::adhesion::pair_stiffness`], summed; `weight`: its share of each, 1 per point;
/// `inv_mass`: 0 for a pinned point, which nothing moves).
#[inline(always)]
pub fn pull_limit(slope_h2: f32, stiffness: f32, weight: f32, inv_mass: f32) -> f32 {
    let q = slope_h2 * stiffness * weight * inv_mass;
    if q > PULL_STIFFNESS_LIMIT {
        PULL_STIFFNESS_LIMIT / q
    } else {
        1.0
    }
}

/// The particle's side of the limit: the factor on a water particle's response to its forces, 1 while
/// `q = slope_h2 · strength_per_mass · stiffness` stays within [`PULL_STIFFNESS_LIMIT`], else
/// `LIMIT / q`. `strength_per_mass`: eq. 2's `s` over the particle's mass, the same for every
/// drop (with held water both scale with the water it holds); `stiffness`: its pairs'
/// [`super::adhesion::pair_stiffness`] times the hair points' weights, summed
/// ([`super::adhesion::Reaction::stiffness`]), which bounds its stiffest restoring mode.
///
/// The factor slows the particle's response to its forces (pulls, gravity, the wind's push):
/// it moves as though that much heavier, while its drag still damps its speed at its own
/// rate, `v' = (v + h f (a + k w)) / (1 + h k)` (`integrate::particle_velocity` with `f a`
/// and `f w`). Where it comes to rest (its forces balanced, the hair carrying exactly its
/// weight) is unchanged, and its pulls' stiffness is held to what the substep follows. Had
/// the damping slowed too (the inertia alone raised), a light drop held past the limit would
/// ring in its well for seconds: its drag's rate falls by the same factor. Its forces cannot
/// take the factor instead, as a hair point's do: the sum is known only once every point has
/// pulled, and a drop's first substep among a groom's light points, unlimited, alone flings
/// it out of reach.
#[inline(always)]
pub fn particle_limit(slope_h2: f32, strength_per_mass: f32, stiffness: f32) -> f32 {
    pull_limit(slope_h2, strength_per_mass, stiffness, 1.0)
}

/// A sum of at most this many stiffnesses is exact to well within [`FREE_MARGIN`], so
/// [`PullLimit::free`] never exceeds it.
const MAX_FREE: u32 = 1000;

/// The relative margin [`PullLimit::free`] keeps below the limit: more than the rounding of a
/// sum of [`MAX_FREE`] terms (`1000 · 2⁻²⁴ = 6e-5`), of each pair's stiffness (a few
/// roundings) and of `q`'s three products.
const FREE_MARGIN: f32 = 1.0e-3;

/// One substep's inputs to the limit.
#[derive(Clone, Copy, Debug)]
pub struct PullLimit {
    /// [`slope_h2`] of the substep and the shell.
    pub slope_h2: f32,
    /// How many candidate particles a row may have with no lane able to reach the limit, all
    /// of them within its reach at full strength and at the distance where a pair is
    /// stiffest ([`super::adhesion::stiffest_pair`]): such a row skips the count (most rows
    /// of heavy hair; none of light hair). 0: every row counts.
    pub free: u32,
    /// Eq. 2's shell, m: each pair's stiffness depends on where in it the particle sits.
    pub r_min: f32,
    /// See `r_min`.
    pub r_max: f32,
}

impl PullLimit {
    /// The limit for a substep `h` and eq. 2's shell. `strongest`: the most strength one
    /// particle can have, when it is known (`s` without absorption; with it, drips may be
    /// heavier than a full particle); `weight_inv_mass`: the largest share times inverse mass
    /// of any hair point ([`crate::plan::water::pull_weight_max`]).
    pub fn new(h: f32, r_min: f32, r_max: f32, strongest: Option<f32>, weight_inv_mass: f32) -> PullLimit {
        let slope_h2 = slope_h2(h, r_min, r_max);
        let free = match strongest {
            Some(s) => {
                let stiffest = s * super::adhesion::stiffest_pair(r_min, r_max);
                let one = slope_h2 * stiffest * weight_inv_mass * (1.0 + FREE_MARGIN);
                if one > 0.0 {
                    (PULL_STIFFNESS_LIMIT / one).min(MAX_FREE as f32) as u32
                } else {
                    MAX_FREE
                }
            }
            None => 0,
        };
        PullLimit {
            slope_h2,
            free,
            r_min,
            r_max,
        }
    }
}

impl PullLimit {
    /// A row's lane weights (`weight`: mask times share, 0 off the row) with the limit
    /// applied, from the particles in grid `runs` of `sorted` (coordinates in grid order),
    /// `strength` of each by grid slot; `inv_mass` the row's. Returns `weight` itself, the
    /// same bits, wherever no lane is past the limit.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn row_weights(
        &self,
        x: &L3,
        weight: &Lane,
        inv_mass: &Lane,
        runs: &[(u32, u32)],
        sorted: [&[f32]; 3],
        strength: impl Fn(u32) -> f32,
    ) -> Lane {
        if !self.counts(runs.iter().map(|&(a, e)| e - a).sum()) {
            return *weight;
        }
        let slots = runs.iter().flat_map(|&(a, e)| a..e);
        let stiffness = self.stiffness_in_reach(x, weight, slots, sorted, strength);
        self.limited(weight, inv_mass, &stiffness)
    }

    /// Whether a row with `candidates` particles that may be within its reach must count
    /// them: past [`PullLimit::free`], some lane could reach the limit.
    #[inline(always)]
    pub fn counts(&self, candidates: u32) -> bool {
        candidates > self.free
    }

    /// A row's lane weights with the limit applied, from each lane's summed stiffness (what
    /// `stiffness_in_reach` sums; the AVX2 gather sums it over its list of particles within
    /// reach, beside its pulls).
    #[inline(always)]
    pub fn limited(&self, weight: &Lane, inv_mass: &Lane, stiffness: &Lane) -> Lane {
        std::array::from_fn(|l| weight[l] * pull_limit(self.slope_h2, stiffness[l], weight[l], inv_mass[l]))
    }

    /// Per lane with a nonzero `weight`, over the particles in `slots` within `r_max`, each
    /// one's strength times the pair's [`pair_stiffness`], summed in the order given (grid
    /// order: the same bits on every run and thread count).
    #[inline]
    fn stiffness_in_reach(
        &self,
        x: &L3,
        weight: &Lane,
        slots: impl Iterator<Item = u32>,
        sorted: [&[f32]; 3],
        strength: impl Fn(u32) -> f32,
    ) -> Lane {
        let (r_min, r_max) = (self.r_min, self.r_max);
        let r2 = r_max * r_max;
        let mut sum = [0.0f32; W];
        for k in slots {
            let j = k as usize;
            let (qx, qy, qz) = (sorted[0][j], sorted[1][j], sorted[2][j]);
            let mut hit = 0u32;
            let mut d2 = [0.0f32; W];
            let mut inside = [false; W];
            for l in 0..W {
                let (dx, dy, dz) = (qx - x.x[l], qy - x.y[l], qz - x.z[l]);
                d2[l] = dx * dx + dy * dy + dz * dz;
                inside[l] = d2[l] <= r2 && weight[l] > 0.0;
                hit |= inside[l] as u32;
            }
            if hit == 0 {
                continue;
            }
            let s = strength(k);
            // Branch-free per lane (a select after the square root and divisions), so that
            // the loop vectorises.
            let stiff: Lane = std::array::from_fn(|l| s * pair_stiffness(d2[l], r_min, r_max));
            for l in 0..W {
                sum[l] += if inside[l] { stiff[l] } else { 0.0 };
            }
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A light point within reach of several particles is held to the limit exactly, a heavy
    /// one keeps its weight's bits, and a pinned one (inverse mass 0) is never limited.
    #[test]
    fn the_limit_caps_light_points_and_leaves_the_rest_alone() {
        let (r_min, r_max, h) = (0.002f32, 0.008f32, 1.0 / 240.0);
        let limit = PullLimit::new(h, r_min, r_max, Some(0.008), 1.0e5);
        assert_eq!(limit.free, 0, "light hair counts every row");
        // Three particles 5 mm from lane 0, all within reach of lanes 0..3 (on one spot).
        let (xs, ys, zs) = (vec![0.005f32; 3], vec![0.0f32; 3], vec![0.0f32; 3]);
        let sorted = [&xs[..], &ys[..], &zs[..]];
        let x = L3::ZERO;
        let weight: Lane = [1.0, 0.5, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
        // 10 mg, 10 mg, 1 g, pinned.
        let inv_mass: Lane = [1.0e5, 1.0e5, 1.0e3, 0.0, 1.0, 1.0, 1.0, 1.0];
        let got = limit.row_weights(&x, &weight, &inv_mass, &[(0, 3)], sorted, |_| 0.008);
        // Each pair at 5 mm, the shell's middle, is held across only: 0.3 of the steepest slope.
        let one = 0.008 * pair_stiffness(0.005 * 0.005, r_min, r_max);
        assert!((one / 0.008 - 0.3).abs() < 1e-6, "{one}");
        let k = one + one + one;
        let q0 = limit.slope_h2 * k * 1.0e5;
        assert!(q0 > 4.0, "the light lane is past symplectic Euler's bound ({q0})");
        assert_eq!(got[0], PULL_STIFFNESS_LIMIT / q0, "held to the limit");
        // Its share halves q: the lane still ends at the limit, the same stiffness.
        let q1 = limit.slope_h2 * k * 0.5 * 1.0e5;
        assert_eq!(got[1], 0.5 * (PULL_STIFFNESS_LIMIT / q1));
        assert_eq!(got[2].to_bits(), 1.0f32.to_bits(), "1 g: within the limit, untouched");
        assert_eq!(got[3].to_bits(), 1.0f32.to_bits(), "pinned: untouched");
        assert_eq!(&got[4..], &[0.0; 4], "lanes off the row stay off");
        // A particle beyond r_max adds nothing.
        let far = [vec![0.0085f32], vec![0.0f32], vec![0.0f32]];
        let sorted = [&far[0][..], &far[1][..], &far[2][..]];
        let none = limit.row_weights(&x, &weight, &inv_mass, &[(0, 1)], sorted, |_| 1.0);
        assert_eq!(none, weight);
    }

    /// The shortcut (every candidate within reach at full strength) never changes a result:
    /// with and without it the weights are the same bits, on rows of random particles, and
    /// heavy hair skips the count on rows of up to `free` candidates.
    #[test]
    fn skipping_the_count_gives_the_counted_bits() {
        let (r_min, r_max) = (0.002f32, 0.008f32);
        let paper = PullLimit::new(1.0 / 240.0, r_min, r_max, Some(0.008), 1.0e3);
        assert_eq!(
            paper.free, 6,
            "a paper-scene point (1 g) takes 6 full pulls at their stiffest at 240 Hz"
        );
        let mut rng = crate::scenes::Lcg(5);
        let mut limited = 0;
        for trial in 0..400 {
            let n = 1 + trial % 23;
            let c: Vec<Vec<f32>> = (0..3)
                .map(|_| (0..n).map(|_| (rng.next_f32() - 0.5) * 0.012).collect())
                .collect();
            let sorted = [&c[0][..], &c[1][..], &c[2][..]];
            let x = L3 {
                x: std::array::from_fn(|_| (rng.next_f32() - 0.5) * 0.004),
                y: std::array::from_fn(|_| (rng.next_f32() - 0.5) * 0.004),
                z: std::array::from_fn(|_| (rng.next_f32() - 0.5) * 0.004),
            };
            let weight: Lane = std::array::from_fn(|_| rng.next_f32());
            let heaviest = 10f32.powf(2.0 + 2.0 * rng.next_f32());
            let inv_mass: Lane = std::array::from_fn(|_| heaviest * rng.next_f32());
            let h = 1.0 / (60.0 * (1 + trial % 8) as f32);
            let quick = PullLimit::new(h, r_min, r_max, Some(0.008), heaviest);
            let counted = PullLimit { free: 0, ..quick };
            let runs = [(0, n as u32)];
            let a = quick.row_weights(&x, &weight, &inv_mass, &runs, sorted, |_| 0.008);
            let b = counted.row_weights(&x, &weight, &inv_mass, &runs, sorted, |_| 0.008);
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "trial {trial}");
            limited += (b != weight) as u32;
        }
        assert!(limited > 40, "the rows reach the limit too ({limited} of 400)");
    }
}
