//! Hair-hair volume (docs/VOLUME.md): a grid in head space over everywhere the hair can reach,
//! the hair's mass and momentum spread onto it by trilinear weights in fixed point (so sums
//! are exact in any order: any thread count, and GPU atomics, give the same grid), and the
//! response each free point takes from it: friction toward the grid's velocity, and a pressure
//! down the density gradient where the hair is denser than at rest. Both backends run these
//! functions (`volume.wgsl` mirrors them).

use crate::error::{Error, Result};
use crate::groom::Groom;
use crate::physics::rounding::round_i64;
use glam::{Mat3, Vec3};

/// Mass per fixed-point unit, kg: a million points of 10 mg each sum far inside an i64.
pub const MASS_QUANTUM: f64 = 1e-15;
/// Momentum per fixed-point unit, kg·m/s.
pub const MOMENTUM_QUANTUM: f64 = 1e-15;
/// Speeds above this are clamped before they are spread (a blown-up point cannot overflow the
/// sums; the step reports it anyway), m/s.
pub const MAX_SPREAD_SPEED: f32 = 1000.0;
/// The most cells a volume grid may have.
pub const MAX_VOLUME_CELLS: usize = 1 << 21;

/// The grid: `dims` samples `cell` apart from `origin`, in head space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeGrid {
    /// The first sample, m (head space).
    pub origin: Vec3,
    /// Spacing, m.
    pub cell: f32,
    /// Samples along x, y, z (each >= 2).
    pub dims: [u32; 3],
}

/// One sample's sums, in quanta.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CellSums {
    /// Mass.
    pub mass: i64,
    /// Momentum, x y z.
    pub momentum: [i64; 3],
}

impl CellSums {
    /// Adds `o` (wrapping: the sums cannot reach i64's range, see [`MASS_QUANTUM`]).
    #[inline(always)]
    pub fn add(&mut self, o: &CellSums) {
        self.mass = self.mass.wrapping_add(o.mass);
        for k in 0..3 {
            self.momentum[k] = self.momentum[k].wrapping_add(o.momentum[k]);
        }
    }
}

/// What a point sees of the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeSample {
    /// Density beyond the rest density, kg/m³ (0 where the hair is no denser than at rest).
    pub density: f32,
    /// Its gradient, kg/m⁴ (head space).
    pub gradient: Vec3,
    /// The hair's velocity there (momentum over mass), m/s; zero where no mass is.
    pub velocity: Vec3,
}

impl VolumeGrid {
    /// A grid of `cell` over everywhere `groom`'s hair can reach: its roots' box grown by the
    /// longest strand (and a cell) on every side. Refused past [`MAX_VOLUME_CELLS`].
    pub fn for_groom(groom: &Groom, cell: f32) -> Result<VolumeGrid> {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for s in 0..groom.strand_count() {
            let r = groom.positions()[groom.strand_range(s).start];
            lo = lo.min(r);
            hi = hi.max(r);
        }
        let reach = groom.max_strand_length() + cell;
        let (lo, hi) = (lo - Vec3::splat(reach), hi + Vec3::splat(reach));
        let n = ((hi - lo) / cell).ceil() + Vec3::ONE;
        let cells = n.x as f64 * n.y as f64 * n.z as f64;
        if !cells.is_finite() || cells > MAX_VOLUME_CELLS as f64 {
            return Err(Error::Capacity(format!(
                "the volume grid of {cell} m cells over {:.2} × {:.2} × {:.2} m needs {cells:.0} cells, more than {MAX_VOLUME_CELLS}; raise volume.cell",
                hi.x - lo.x,
                hi.y - lo.y,
                hi.z - lo.z
            )));
        }
        Ok(VolumeGrid {
            origin: lo,
            cell,
            dims: [n.x as u32, n.y as u32, n.z as u32],
        })
    }

    /// Number of samples.
    pub fn cells(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }

    /// The cell holding `p` (head space): its lower sample's index and the fractions within;
    /// `None` outside the grid.
    #[inline(always)]
    pub fn locate(&self, p: Vec3) -> Option<(usize, Vec3)> {
        let g = (p - self.origin) / self.cell;
        let [nx, ny, nz] = self.dims;
        let top = Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32);
        if !(g.cmpge(Vec3::ZERO).all() && g.cmple(top).all()) {
            return None;
        }
        let i = (g.x as u32).min(nx - 2);
        let j = (g.y as u32).min(ny - 2);
        let k = (g.z as u32).min(nz - 2);
        let f = g - Vec3::new(i as f32, j as f32, k as f32);
        Some((i as usize + nx as usize * (j as usize + ny as usize * k as usize), f))
    }

    /// The eight samples of a cell from its lower one, x fastest.
    #[inline(always)]
    pub fn corners(&self, base: usize) -> [usize; 8] {
        let (sx, sy) = (self.dims[0] as usize, self.dims[0] as usize * self.dims[1] as usize);
        [
            base,
            base + 1,
            base + sx,
            base + sx + 1,
            base + sy,
            base + sy + 1,
            base + sy + sx,
            base + sy + sx + 1,
        ]
    }
}

/// The trilinear weights of the eight corners (x fastest).
#[inline(always)]
pub fn weights(f: Vec3) -> [f32; 8] {
    let (gx, gy, gz) = (1.0 - f.x, 1.0 - f.y, 1.0 - f.z);
    [
        gx * gy * gz,
        f.x * gy * gz,
        gx * f.y * gz,
        f.x * f.y * gz,
        gx * gy * f.z,
        f.x * gy * f.z,
        gx * f.y * f.z,
        f.x * f.y * f.z,
    ]
}

/// Bits of a corner's fixed-point weight along one axis.
pub const AXIS_WEIGHT_BITS: u32 = 16;

/// A point's mass and momentum in quanta, rounded once (the speed clamped first).
#[inline(always)]
pub fn point_quanta(mass: f32, v: Vec3) -> [i64; 4] {
    let v = v.clamp(Vec3::splat(-MAX_SPREAD_SPEED), Vec3::splat(MAX_SPREAD_SPEED));
    let m = mass as f64;
    let (to_mass, to_momentum) = (1.0 / MASS_QUANTUM, 1.0 / MOMENTUM_QUANTUM);
    [
        round_i64(m * to_mass),
        round_i64(m * v.x as f64 * to_momentum),
        round_i64(m * v.y as f64 * to_momentum),
        round_i64(m * v.z as f64 * to_momentum),
    ]
}

/// The eight corners' trilinear weights (x fastest) in fixed point: each axis's fraction in
/// 1/2^16 and its complement, multiplied, so the eight sum to exactly 2^48.
#[inline(always)]
pub fn fixed_weights(f: Vec3) -> [i64; 8] {
    let one = 1i64 << AXIS_WEIGHT_BITS;
    let axis = |t: f32| {
        let hi = (round_i64(t as f64 * one as f64)).clamp(0, one);
        [one - hi, hi]
    };
    let (x, y, z) = (axis(f.x), axis(f.y), axis(f.z));
    std::array::from_fn(|c| x[c & 1] * y[(c >> 1) & 1] * z[c >> 2])
}

/// `q` times the fixed-point weight `w` (of 2^48), floored: a corner's share of a point's
/// quanta, in integers (one 64 × 64 → 128-bit multiply).
#[inline(always)]
fn share_of(q: i64, w: i64) -> i64 {
    ((q as i128 * w as i128) >> (3 * AXIS_WEIGHT_BITS)) as i64
}

/// The mass a point of `mass` and `wetness` spreads: its dry share. Wet hair leaves the
/// volume as it soaks: the bundles water pulls together do not count toward the density that
/// pushes hair apart (nor toward the velocity its neighbours are smoothed to), so the pressure
/// of the dry hair around them does not spread them again.
#[inline(always)]
pub fn spread_mass(mass: f32, wetness: f32) -> f32 {
    mass * (1.0 - wetness.clamp(0.0, 1.0))
}

/// Spreads a point of `mass` at `p` (head space) moving at `v` onto `sums`; nothing outside.
/// The point's quanta are rounded once and shared among its corners by integer weights (a
/// share rounded per corner, 32 roundings a point, cost most of the pass).
#[inline(always)]
pub fn spread(grid: &VolumeGrid, sums: &mut [CellSums], p: Vec3, v: Vec3, mass: f32) {
    let Some((base, f)) = grid.locate(p) else {
        return;
    };
    let q = point_quanta(mass, v);
    for (c, w) in grid.corners(base).into_iter().zip(fixed_weights(f)) {
        sums[c].add(&CellSums {
            mass: share_of(q[0], w),
            momentum: [share_of(q[1], w), share_of(q[2], w), share_of(q[3], w)],
        });
    }
}

/// What a point at `p` (head space) sees: the density's excess over `rest` (kg/m³) and its
/// gradient, and the hair's velocity. The excess is taken at the samples, so the pressure
/// starts smoothly where the hair first packs past its rest density.
#[inline(always)]
pub fn sample(grid: &VolumeGrid, sums: &[CellSums], p: Vec3, rest: f32) -> Option<VolumeSample> {
    let (base, f) = grid.locate(p)?;
    let corners = grid.corners(base);
    let per_volume = (MASS_QUANTUM / (grid.cell as f64).powi(3)) as f32;
    let rho: [f32; 8] = corners.map(|c| (sums[c].mass as f32 * per_volume - rest).max(0.0));
    let (density, gradient) = super::trilinear::trilinear(&rho, f);
    let w = weights(f);
    let (mut m, mut pm) = (0.0f32, Vec3::ZERO);
    for (c, wc) in corners.into_iter().zip(w) {
        m += wc * sums[c].mass as f32;
        let q = sums[c].momentum;
        pm += wc * Vec3::new(q[0] as f32, q[1] as f32, q[2] as f32);
    }
    let ratio = (MOMENTUM_QUANTUM / MASS_QUANTUM) as f32;
    let velocity = if m > 0.0 { pm * (ratio / m) } else { Vec3::ZERO };
    Some(VolumeSample {
        density,
        gradient: gradient / grid.cell,
        velocity,
    })
}

/// The step's constants of the response.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeLaw {
    /// `1 - exp(-friction dt)`.
    pub blend: f32,
    /// `pressure dt / rest_density` (0 without pressure).
    pub push: f32,
    /// Head-space gradients to world ones: the inverse transpose of the head's linear part.
    pub to_world: Mat3,
}

impl VolumeLaw {
    /// The law for a step of `dt` under the head's linear part `head`.
    pub fn new(p: &crate::params::Volume, rest_density: f32, dt: f32, head: Mat3) -> VolumeLaw {
        VolumeLaw {
            blend: 1.0 - (-p.friction * dt).exp(),
            push: if rest_density > 0.0 {
                p.pressure * dt / rest_density
            } else {
                0.0
            },
            to_world: head.inverse().transpose(),
        }
    }
}

/// A free point's velocity after the volume's response to what it sees. Wet hair loses its
/// volume: the pressure falls with the point's wetness (0 dry, 1 soaked), so the bundles water
/// pulls together are not pushed apart again.
#[inline(always)]
pub fn respond(v: Vec3, s: &VolumeSample, law: &VolumeLaw, wetness: f32) -> Vec3 {
    let v = v + (s.velocity - v) * law.blend;
    if s.density > 0.0 {
        v - law.to_world * s.gradient * (law.push * (1.0 - wetness.clamp(0.0, 1.0)))
    } else {
        v
    }
}

/// Of the rest densities free points see, the one [`REST_QUANTILE`] of the hair's mass is
/// below: pressure then leaves the rest pose nearly alone and acts where the hair packs
/// tighter than almost anywhere at rest.
pub const REST_QUANTILE: f64 = 0.9;

/// The rest density `p` gives, or, where it gives none, `groom`'s measured ([`rest_density`]).
pub fn rest_density_of(p: &crate::params::Volume, grid: &VolumeGrid, groom: &Groom) -> f32 {
    if p.rest_density > 0.0 {
        p.rest_density
    } else {
        rest_density(grid, groom)
    }
}

/// The rest density of `groom` ([`REST_QUANTILE`]), kg/m³.
pub fn rest_density(grid: &VolumeGrid, groom: &Groom) -> f32 {
    let free = || {
        groom
            .positions()
            .iter()
            .zip(groom.masses())
            .zip(groom.pinned())
            .filter(|(_, pinned)| !**pinned)
            .map(|(pm, _)| pm)
    };
    let mut sums = vec![CellSums::default(); grid.cells()];
    for (p, m) in free() {
        spread(grid, &mut sums, *p, Vec3::ZERO, *m);
    }
    let mut seen: Vec<(f32, f32)> = free()
        .filter_map(|(p, m)| sample(grid, &sums, *p, 0.0).map(|s| (s.density, *m)))
        .collect();
    seen.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = seen.iter().map(|s| s.1 as f64).sum();
    let mut below = 0.0f64;
    for (rho, m) in &seen {
        below += *m as f64;
        if below >= REST_QUANTILE * total {
            return *rho;
        }
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> VolumeGrid {
        VolumeGrid {
            origin: Vec3::splat(-0.1),
            cell: 0.01,
            dims: [21, 21, 21],
        }
    }

    #[test]
    fn spread_mass_and_momentum_sum_back_and_in_any_order() {
        let g = grid();
        let pts: Vec<(Vec3, Vec3, f32)> = (0..200)
            .map(|i| {
                let t = i as f32 * 0.37;
                (
                    Vec3::new(t.sin(), t.cos(), (2.0 * t).sin()) * 0.08,
                    Vec3::new(1.0, -0.5, 0.2) * t.cos(),
                    1e-6 * (1.0 + (i % 7) as f32),
                )
            })
            .collect();
        let mut a = vec![CellSums::default(); g.cells()];
        let mut b = a.clone();
        for (p, v, m) in &pts {
            spread(&g, &mut a, *p, *v, *m);
        }
        for (p, v, m) in pts.iter().rev() {
            spread(&g, &mut b, *p, *v, *m);
        }
        assert_eq!(a, b, "exact in any order");
        let total: i64 = a.iter().map(|c| c.mass).sum();
        let want: f64 = pts.iter().map(|(_, _, m)| *m as f64).sum();
        assert!(
            (total as f64 * MASS_QUANTUM - want).abs() < 1e-6 * want,
            "the mass spread is the mass"
        );
        // A uniform velocity reads back as itself anywhere there is mass.
        let mut u = vec![CellSums::default(); g.cells()];
        for (p, _, m) in &pts {
            spread(&g, &mut u, *p, Vec3::new(0.3, -0.2, 0.1), *m);
        }
        let s = sample(&g, &u, pts[5].0, 0.0).unwrap();
        assert!(
            (s.velocity - Vec3::new(0.3, -0.2, 0.1)).length() < 1e-4,
            "{:?}",
            s.velocity
        );
    }

    #[test]
    fn the_gradient_points_up_the_density_and_the_push_goes_down_it() {
        let g = grid();
        let mut sums = vec![CellSums::default(); g.cells()];
        // A dense clump at x = 0.02.
        for k in 0..50 {
            spread(&g, &mut sums, Vec3::new(0.02, 0.001 * k as f32, 0.0), Vec3::ZERO, 1e-6);
        }
        let s = sample(&g, &sums, Vec3::new(0.015, 0.02, 0.0), 0.0).unwrap();
        assert!(s.gradient.x > 0.0, "{:?}", s.gradient);
        let law = VolumeLaw::new(&crate::params::Volume::ON, s.density * 0.5, 1.0 / 60.0, Mat3::IDENTITY);
        let v = respond(Vec3::ZERO, &s, &law, 0.0);
        assert!(v.x < 0.0, "pushed away from the clump: {v}");
        assert_eq!(
            respond(Vec3::ZERO, &s, &law, 1.0),
            Vec3::ZERO,
            "soaked hair is not pushed"
        );
        // Below the rest density nothing pushes.
        let calm = sample(&g, &sums, Vec3::new(0.015, 0.02, 0.0), 1e9).unwrap();
        assert_eq!((calm.density, calm.gradient), (0.0, Vec3::ZERO));
        assert!(sample(&g, &sums, Vec3::splat(0.2), 0.0).is_none(), "outside the grid");
    }
}
