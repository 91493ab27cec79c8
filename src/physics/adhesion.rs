//! Eq. 2: a water particle pulls nearby hair points onto its surface shell.
//!
//! `g(d) = 1 - ((2d - r_min - r_max) / (r_min - r_max))²` for `d <= r_max`, else 0; the force
//! on hair point i from particle j is `s g(d) (p_j - p_i)/d`, and particle j gets the opposite.
//! `g` is 0 at `r_min` and `r_max`, 1 halfway, negative (repulsive) inside `r_min`.

use super::lanes::{hsum, Lane, L3, W};
use super::pull_limit::PullLimit;
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
    shell(d, r_min, r_max)
}

/// The profile's variable `u = (2d − r_min − r_max) / (r_min − r_max)`: 1 at `r_min`, 0 halfway,
/// −1 at `r_max`.
#[inline(always)]
fn profile_variable(d: f32, r_min: f32, r_max: f32) -> f32 {
    (2.0 * d - r_min - r_max) / (r_min - r_max)
}

/// Eq. 2's parabola without the cut-off at `r_max` (callers apply it).
#[inline(always)]
fn shell(d: f32, r_min: f32, r_max: f32) -> f32 {
    let u = profile_variable(d, r_min, r_max);
    1.0 - u * u
}

/// The factor `m` such that the force on the hair point is `m (p_j - p_i)`, given
/// `d2 = |p_j - p_i|²`: `s g(d) / d`, and 0 beyond `r_max` or below [`MIN_DISTANCE`].
/// Branch-free: the value is computed whatever the distance and a select keeps the reach, so
/// that a loop over lanes ([`force_scale_lanes`]) vectorises.
#[inline(always)]
pub fn force_scale(d2: f32, r_min: f32, r_max: f32, s: f32) -> f32 {
    let inside = (d2 <= r_max * r_max) & (d2 >= MIN_DISTANCE * MIN_DISTANCE);
    let d = d2.sqrt();
    let v = s * shell(d, r_min, r_max) / d;
    if inside {
        v
    } else {
        0.0
    }
}

/// How stiffly a particle at squared distance `d2` and a hair point hold each other, per unit
/// of the pull's strength and in units of the profile's steepest slope `4 / (r_max − r_min)`:
/// the largest restoring eigenvalue of the pull's derivative in the particle's position (hair
/// point fixed), or in the hair point's (the same matrix), `max(s g'(d), s g(d) / d)` (along
/// the pair and across it), is `s 4 / (r_max − r_min)` times `max(u, (r_max − r_min) g(d) /
/// 4d)`, `u` the profile's variable, 1 at `r_min` (the across term held to its bound of 1,
/// [`stiffest_pair`]). 0 wherever [`force_scale`] is. By Weyl's inequality a sum of these
/// bounds the stiffest restoring mode under every pair at once, which both sides of the
/// stability limit hold to what a substep follows (`physics/pull_limit.rs` `pull_limit` for
/// a hair point, `particle_limit` for a particle).
#[inline(always)]
pub fn pair_stiffness(d2: f32, r_min: f32, r_max: f32) -> f32 {
    let inside = (d2 <= r_max * r_max) & (d2 >= MIN_DISTANCE * MIN_DISTANCE);
    let d = d2.sqrt();
    let u = profile_variable(d, r_min, r_max);
    let across = (0.25 * (r_max - r_min)) * (1.0 - u * u) / d;
    // At most 1 ([`stiffest_pair`]); held there against rounding, which near the hair point
    // of a shell with no hollow (`r_min` 0) takes `1 − u²` from a difference of two numbers
    // next to 1.
    let across = if across < 1.0 { across } else { 1.0 };
    let k = if u > across { u } else { across };
    if inside {
        k
    } else {
        0.0
    }
}

/// The most [`pair_stiffness`] can be at any distance: `(r_max + r_min) / (r_max − r_min)`,
/// `u` as the particle nears the hair point (1.67 with the paper's shell). Within the shell
/// `u ≤ 1`, and the across term, `w (1 − u)(1 + u) / 2 (w (1 − u) + 2 r_min)` with
/// `w = r_max − r_min`, is at most `(1 + u) / 2 ≤ 1`; inside `r_min` it is negative and `u`
/// grows toward the hair point. The stability limit's shortcut bounds a row's pairs with it.
#[inline]
pub fn stiffest_pair(r_min: f32, r_max: f32) -> f32 {
    ((r_max + r_min) / (r_max - r_min)).max(1.0)
}

/// [`force_scale`] on every lane at once. Written with `&&` and the divide behind the branch,
/// as it once was, the compiler kept a scalar square root and two divides behind a branch per
/// lane, and the eq. 2 pass ran at a quarter of its vector speed.
#[inline(always)]
pub fn force_scale_lanes(d2: &Lane, r_min: f32, r_max: f32, s: f32) -> Lane {
    std::array::from_fn(|l| force_scale(d2[l], r_min, r_max, s))
}

/// The force on a hair point at `hair` from a particle at `water`.
#[inline(always)]
pub fn force_on_hair(hair: Vec3, water: Vec3, r_min: f32, r_max: f32, s: f32) -> Vec3 {
    let d = water - hair;
    d * force_scale(d.length_squared(), r_min, r_max, s)
}

/// Particles stored by grid cell, coordinates apart (structure of arrays), so that one run of
/// cells is one contiguous slice the compiler can vectorise over.
#[derive(Clone, Copy)]
pub struct Run<'a> {
    /// x coordinates.
    pub x: &'a [f32],
    /// y coordinates.
    pub y: &'a [f32],
    /// z coordinates.
    pub z: &'a [f32],
}

/// The reaction of one row of hair points on one particle: what the particle in grid slot
/// `slot` receives (minus the sum of the forces on the row's lanes). Reactions are kept as a
/// list in the order they were found and summed per particle in that order afterwards, so the
/// sum does not depend on how blocks were shared among threads.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Reaction {
    /// The particle's grid slot.
    pub slot: u32,
    /// Force on the particle, N.
    pub f: [f32; 3],
    /// How stiffly the row holds the particle, per unit of its strength and in the profile's
    /// steepest slopes: [`pair_stiffness`] times each lane's weight (its share with the hair
    /// side's limit), summed over the lanes. The particle's side of the stability limit
    /// (`physics/pull_limit.rs` `particle_limit`) sums it.
    pub stiffness: f32,
}

/// Eq. 2's strength of each particle the gather reads, by grid slot: `s` itself, or `s` times
/// the drops a slot stands for where drops piled within one cell pull as one source
/// (`cpu/piles.rs`). With held water the strength comes from each particle's water instead
/// (`absorb::WetRow::strength`).
#[derive(Clone, Copy, Debug)]
pub struct Strength<'a> {
    /// Eq. 2's `s`, N.
    pub s: f32,
    /// Drops per grid slot; empty where every slot is one drop.
    pub drops: &'a [f32],
}

impl Strength<'_> {
    /// Every particle pulls with `s`.
    pub fn uniform(s: f32) -> Strength<'static> {
        Strength { s, drops: &[] }
    }

    /// The strength of the particle in grid `slot`.
    #[inline(always)]
    pub fn of(&self, slot: u32) -> f32 {
        match self.drops.get(slot as usize) {
            Some(&n) => self.s * n,
            None => self.s,
        }
    }

    /// The most strength one slot has (`s` times the largest pile).
    pub fn strongest(&self) -> f32 {
        self.s * self.drops.iter().copied().fold(1.0, f32::max)
    }
}

/// Eq. 2 between the `W` hair points of a lane row (`mask[l]` is 1 for lanes to include, 0
/// otherwise) and every particle of a run, whose first particle sits in grid slot
/// `first_slot`. Each lane's pull is scaled by `weight[l]`: its mask times its share of the
/// pull where eq. 2 is quoted per length of hair (`physics/per_length.rs`), the mask itself
/// where it is per point. Adds the forces on the hair lanes to `acc`, marks in `near` the lanes with a
/// particle within `r_max`, and appends each touched particle's reaction (minus the sum over
/// lanes) to `reactions`. One particle against eight hair points is one SIMD pass. With held
/// water (`wet`), each particle pulls with `s` scaled by the water it holds, and the lanes it
/// reaches ask it for water (docs/WET_MODEL.md §2). In a guide groom each lane's reaction and
/// stiffness are its `bundle`'s: a guide pulls the particle back with the hair of every
/// strand it stands for (`physics/bundles.rs`), its own point with its own.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn gather_run_lanes(
    x: &L3,
    mask: &Lane,
    weight: &Lane,
    bundle: Option<&Lane>,
    run: Run,
    first_slot: u32,
    reactions: &mut Vec<Reaction>,
    acc: &mut L3,
    near: &mut Lane,
    r_min: f32,
    r_max: f32,
    s: Strength,
    mut wet: Option<&mut super::absorb::WetRow>,
) {
    let r2 = r_max * r_max;
    // The marks accumulate in a local (a register) and are written back once: through the
    // caller's `near` every candidate waited on the last one's store.
    let mut marks = *near;
    let parts = run.x.iter().zip(run.y).zip(run.z);
    for (j, ((&qx, &qy), &qz)) in parts.enumerate() {
        let mut d2s = [0.0f32; W];
        let mut inside = [0.0f32; W];
        let mut hit = 0u32;
        for l in 0..W {
            let (dx, dy, dz) = (qx - x.x[l], qy - x.y[l], qz - x.z[l]);
            d2s[l] = dx * dx + dy * dy + dz * dz;
            inside[l] = if d2s[l] <= r2 { mask[l] } else { 0.0 };
            // Marks and mask are 0 or 1 (never NaN): a compare and select is the max.
            marks[l] = if inside[l] > marks[l] { inside[l] } else { marks[l] };
            // An integer OR, not a float sum: it reduces in a tree instead of a serial chain.
            hit |= (inside[l] > 0.0) as u32;
        }
        if hit == 0 {
            continue; // no lane within r_max of this particle
        }
        let slot = first_slot + j as u32;
        let s_j = match wet.as_deref_mut() {
            Some(w) => {
                w.demand(slot, &d2s, &inside, r_min, r_max);
                w.strength(slot)
            }
            None => s.of(slot),
        };
        let (mut rx, mut ry, mut rz) = ([0.0f32; W], [0.0f32; W], [0.0f32; W]);
        let mut stiff = [0.0f32; W];
        let scale = force_scale_lanes(&d2s, r_min, r_max, s_j);
        for l in 0..W {
            stiff[l] = pair_stiffness(d2s[l], r_min, r_max) * weight[l];
            let m = scale[l] * weight[l];
            rx[l] = m * (qx - x.x[l]);
            ry[l] = m * (qy - x.y[l]);
            rz[l] = m * (qz - x.z[l]);
            acc.x[l] += rx[l];
            acc.y[l] += ry[l];
            acc.z[l] += rz[l];
        }
        if let Some(b) = bundle {
            for l in 0..W {
                (rx[l], ry[l], rz[l]) = (rx[l] * b[l], ry[l] * b[l], rz[l] * b[l]);
                stiff[l] *= b[l];
            }
        }
        reactions.push(Reaction {
            slot,
            f: [-hsum(&rx), -hsum(&ry), -hsum(&rz)],
            stiffness: hsum(&stiff),
        });
    }
    *near = marks;
}

/// [`gather_run_lanes`] over each run `(start, end)` of grid slots in `runs`, the particles'
/// coordinates in grid order in `sorted`: one row's whole gather.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn gather_runs_lanes(
    x: &L3,
    mask: &Lane,
    weight: &Lane,
    bundle: Option<&Lane>,
    runs: &[(u32, u32)],
    sorted: [&[f32]; 3],
    reactions: &mut Vec<Reaction>,
    acc: &mut L3,
    near: &mut Lane,
    r_min: f32,
    r_max: f32,
    s: Strength,
    mut wet: Option<&mut super::absorb::WetRow>,
) {
    for &(a, e) in runs {
        let (a0, e0) = (a as usize, e as usize);
        let run = Run {
            x: &sorted[0][a0..e0],
            y: &sorted[1][a0..e0],
            z: &sorted[2][a0..e0],
        };
        gather_run_lanes(
            x,
            mask,
            weight,
            bundle,
            run,
            a,
            reactions,
            acc,
            near,
            r_min,
            r_max,
            s,
            wet.as_deref_mut(),
        );
    }
}

/// One row's whole gather under eq. 2's stability limit (`physics/pull_limit.rs`): the lanes'
/// weights limited from their inverse masses `inv_mass` and the particles within reach, then
/// [`gather_runs_lanes`] with them. The lane form of `adhesion_avx2::gather_row_lanes`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn gather_row_lanes(
    x: &L3,
    mask: &Lane,
    weight: &Lane,
    bundle: Option<&Lane>,
    inv_mass: &Lane,
    limit: &PullLimit,
    runs: &[(u32, u32)],
    sorted: [&[f32]; 3],
    reactions: &mut Vec<Reaction>,
    acc: &mut L3,
    near: &mut Lane,
    r_min: f32,
    r_max: f32,
    s: Strength,
    wet: Option<&mut super::absorb::WetRow>,
) {
    let limited = {
        let strength = |slot| wet.as_deref().map_or_else(|| s.of(slot), |w| w.strength(slot));
        limit.row_weights(x, weight, inv_mass, runs, sorted, strength)
    };
    gather_runs_lanes(
        x, mask, &limited, bundle, runs, sorted, reactions, acc, near, r_min, r_max, s, wet,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pulls' restoring stiffness on a particle (minus the derivative of its force in its
    /// position, hair fixed), by central differences of [`force_on_hair`], as a symmetric
    /// 3x3's largest eigenvalue (power iteration on it shifted to be positive definite).
    fn stiffest_mode(hair: &[Vec3], water: Vec3, r_min: f32, r_max: f32, s: f32) -> f32 {
        let e = 1.0e-6f32;
        let force = |y: Vec3| -> glam::DVec3 {
            hair.iter()
                .map(|&x| -force_on_hair(x, y, r_min, r_max, s).as_dvec3())
                .sum()
        };
        let cols: [glam::DVec3; 3] = std::array::from_fn(|a| {
            let d = Vec3::AXES[a] * e;
            -(force(water + d) - force(water - d)) / (2.0 * e as f64)
        });
        let k = glam::DMat3::from_cols(cols[0], cols[1], cols[2]);
        let k = (k + k.transpose()) * 0.5;
        let shifted = k + glam::DMat3::IDENTITY * (k.x_axis.length() + k.y_axis.length() + k.z_axis.length());
        let mut v = glam::DVec3::new(0.3, 0.5, 0.8).normalize();
        for _ in 0..200 {
            v = (shifted * v).normalize_or(v);
        }
        v.dot(k * v) as f32
    }

    /// [`pair_stiffness`] is one pair's stiffest restoring mode at every distance in the
    /// shell (along the pair inside the profile's peak, across it outside), and their sum
    /// bounds the mode of many pairs at once (Weyl's inequality), which the particle's side of
    /// the stability limit relies on.
    #[test]
    fn pair_stiffness_bounds_the_particles_stiffest_mode() {
        let (r_min, r_max, s) = (0.002f32, 0.008f32, 0.008f32);
        let steepest = s * 4.0 / (r_max - r_min);
        for d in [0.0025f32, 0.004, 0.005, 0.006, 0.0075] {
            let hair = [Vec3::new(d, 0.0, 0.0)];
            let want = stiffest_mode(&hair, Vec3::ZERO, r_min, r_max, s);
            let got = steepest * pair_stiffness(d * d, r_min, r_max);
            assert!((got - want).abs() <= 2e-3 * steepest, "d {d}: {got} against {want}");
        }
        let mut rng = crate::scenes::Lcg(9);
        for trial in 0..50 {
            let hair: Vec<Vec3> = (0..1 + trial % 40)
                .map(|_| (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5) * 0.014)
                .collect();
            let mode = stiffest_mode(&hair, Vec3::ZERO, r_min, r_max, s);
            let bound: f32 = hair
                .iter()
                .map(|x| steepest * pair_stiffness(x.length_squared(), r_min, r_max))
                .sum();
            assert!(
                mode <= bound * 1.001 + 1e-3,
                "trial {trial}: mode {mode} above the bound {bound}"
            );
        }
    }

    /// No distance gives a pair more stiffness than [`stiffest_pair`] (what the stability
    /// limit's shortcut assumes), and the bound is reached: near the hair point for a shell
    /// with a hollow, at the inner edge for one without (`r_min` 0).
    #[test]
    fn no_pair_is_stiffer_than_the_stiffest() {
        for (r_min, r_max) in [(0.002f32, 0.008f32), (0.0, 0.008), (0.0005, 0.02), (0.007, 0.008)] {
            let most = stiffest_pair(r_min, r_max);
            let mut seen = 0.0f32;
            for k in 0..=200_000 {
                let d = MIN_DISTANCE + r_max * k as f32 / 200_000.0;
                let got = pair_stiffness(d * d, r_min, r_max);
                assert!(
                    got <= most * (1.0 + 1e-5),
                    "r {r_min}..{r_max}, d {d}: {got} above {most}"
                );
                seen = seen.max(got);
            }
            assert!(
                seen >= most * 0.999,
                "r {r_min}..{r_max}: the bound {most} is not reached ({seen})"
            );
        }
    }

    /// The lane form gives the one-point form's bits on every lane: inside the shell, at its
    /// edges, beyond `r_max`, below the minimum distance and at 0.
    #[test]
    fn lanes_give_the_one_point_bits() {
        let (r_min, r_max, s) = (0.003f32, 0.009f32, 7.5f32);
        let mut rng = crate::scenes::Lcg(11);
        let mut d2s: Vec<f32> = (0..4000).map(|_| (rng.next_f32() * 0.012).powi(2)).collect();
        d2s.extend([
            0.0,
            1e-20,
            1e-18,
            r_min * r_min,
            r_max * r_max,
            r_max * r_max * 1.0001,
            1.0,
        ]);
        d2s.resize(d2s.len().next_multiple_of(W), 0.5 * r_max * r_max);
        for chunk in d2s.chunks(W) {
            let lanes: Lane = chunk.try_into().unwrap();
            let got = force_scale_lanes(&lanes, r_min, r_max, s);
            for l in 0..W {
                let want = force_scale(lanes[l], r_min, r_max, s);
                assert_eq!(got[l].to_bits(), want.to_bits(), "d2 {}", lanes[l]);
            }
        }
    }
}
