//! Signed distance field colliders: a grid of distances (negative inside) that the host gives
//! once, placed in the world by a transform it may change every frame. A hair point found
//! inside (trilinear distance below zero) is moved out along the field's gradient by the
//! distance, and its velocity answers as at an analytic collider (`collide.rs` `respond`: the
//! part into the surface removed, the tangential part scaled by `1 - friction`). Outside the
//! grid's box nothing collides.

use super::collide::respond_moving;
pub use super::frames::{check_transform, transform_from_mat4, UNIFORM_SCALE_TOLERANCE};
use super::lanes::{Lane, L3, W};
use crate::error::{invalid, Error, Result};
use glam::{Affine3A, Vec3};

/// Most SDF colliders per simulation.
pub const MAX_SDFS: usize = 16;
/// Most cells in one grid (64 MiB of f32).
pub const MAX_SDF_CELLS: u64 = 1 << 24;

/// A signed distance grid: `values[i + nx (j + ny k)]` is the distance, m, from the point
/// `origin + cell (i, j, k)` of the grid's own frame to the surface, negative inside.
#[derive(Clone, Debug, PartialEq)]
pub struct Sdf {
    /// Samples along x, y and z, each at least 2.
    pub dims: [u32; 3],
    /// The first sample's position in the grid's frame, m.
    pub origin: Vec3,
    /// Spacing of the samples, m, > 0.
    pub cell: f32,
    /// Distances, m, x fastest (`dims` product of them).
    pub values: Vec<f32>,
    /// Where the grid's frame sits in the world at the start (rotation, translation and a
    /// uniform scale; `Simulation::set_sdf_transform` moves it).
    pub transform: Affine3A,
}

impl Sdf {
    /// The grid of `shape` sampled on `dims` points from `origin` at `cell` spacing (tests
    /// and hosts that build a field from a function).
    pub fn from_fn(dims: [u32; 3], origin: Vec3, cell: f32, f: impl Fn(Vec3) -> f32) -> Sdf {
        let mut values = Vec::with_capacity(dims.iter().map(|&d| d as usize).product());
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    values.push(f(origin + cell * Vec3::new(i as f32, j as f32, k as f32)));
                }
            }
        }
        Sdf {
            dims,
            origin,
            cell,
            values,
            transform: Affine3A::IDENTITY,
        }
    }

    /// Checks the grid: dimensions, cell, origin, every value, the transform.
    pub fn validate(&self, name: &str) -> Result<()> {
        if self.dims.iter().any(|&d| d < 2) {
            return Err(invalid!(
                "{name}: dims must be at least 2 on each axis, got {:?}",
                self.dims
            ));
        }
        let cells: u64 = self.dims.iter().map(|&d| d as u64).product();
        if cells > MAX_SDF_CELLS {
            return Err(Error::Capacity(format!(
                "{name}: {cells} samples exceed {MAX_SDF_CELLS}"
            )));
        }
        if self.values.len() as u64 != cells {
            return Err(invalid!(
                "{name}: {} values for dims {:?} ({cells} needed)",
                self.values.len(),
                self.dims
            ));
        }
        if !(self.cell.is_finite() && self.cell > 0.0) {
            return Err(invalid!("{name}: cell must be finite and > 0, got {}", self.cell));
        }
        if !self.origin.is_finite() {
            return Err(invalid!("{name}: origin has a non-finite entry"));
        }
        if let Some(i) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(invalid!("{name}: value {i} is not finite"));
        }
        check_transform(&self.transform, name)
    }

    /// Trilinear distance and its gradient at `p` (grid frame), or `None` outside the grid.
    #[inline]
    pub fn sample(&self, p: Vec3) -> Option<(f32, Vec3)> {
        let (c, f) = self.cell_at((p - self.origin) / self.cell)?;
        let (d, g) = super::trilinear::trilinear(&c, f);
        Some((d, g / self.cell))
    }

    /// The eight corner values (x fastest) and the fractions within of the cell holding `g`
    /// (grid frame, in cells from the first sample), or `None` outside the grid.
    #[inline(always)]
    fn cell_at(&self, g: Vec3) -> Option<([f32; 8], Vec3)> {
        let [nx, ny, nz] = self.dims;
        let top = Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32);
        if !(g.cmpge(Vec3::ZERO).all() && g.cmple(top).all()) {
            return None;
        }
        // The cell's lower corner, kept one short of the last sample so a point on the far
        // face uses the last cell with weight 1.
        let i = (g.x as u32).min(nx - 2) as usize;
        let j = (g.y as u32).min(ny - 2) as usize;
        let k = (g.z as u32).min(nz - 2) as usize;
        let f = g - Vec3::new(i as f32, j as f32, k as f32);
        let (sx, sy) = (nx as usize, nx as usize * ny as usize);
        let at = |di: usize, dj: usize, dk: usize| self.values[(i + di) + sx * (j + dj) + sy * (k + dk)];
        let c = [
            at(0, 0, 0),
            at(1, 0, 0),
            at(0, 1, 0),
            at(1, 1, 0),
            at(0, 0, 1),
            at(1, 0, 1),
            at(0, 1, 1),
            at(1, 1, 1),
        ];
        Some((c, f))
    }

    /// The grid's box in its own frame: lower and upper corners.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let [nx, ny, nz] = self.dims;
        let top = Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32) * self.cell;
        (self.origin, self.origin + top)
    }
}

/// An SDF placed for one substep: world to grid frame, the grid frame's linear part back
/// (normals), the scale (distances), and the world box that holds the grid (a cheap reject).
#[derive(Clone, Copy, Debug)]
pub struct PlacedSdf {
    /// World to grid frame.
    pub to_grid: Affine3A,
    /// Grid frame to world.
    pub to_world: Affine3A,
    /// The transform's uniform scale.
    pub scale: f32,
    /// World box around the grid: lower and upper corners.
    pub lo: Vec3,
    /// Upper corner.
    pub hi: Vec3,
    /// The surface's velocity field over the substep, m/s: a point fixed in the grid's frame
    /// at world `p` moves at `velocity.transform_point3(p)` (zero for a still field).
    pub velocity: Affine3A,
}

impl PlacedSdf {
    /// `sdf` placed by `t` (grid frame to world).
    pub fn new(sdf: &Sdf, t: &Affine3A) -> PlacedSdf {
        let (a, b) = sdf.bounds();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for c in 0..8 {
            let p = Vec3::new(
                if c & 1 == 0 { a.x } else { b.x },
                if c & 2 == 0 { a.y } else { b.y },
                if c & 4 == 0 { a.z } else { b.z },
            );
            let w = t.transform_point3(p);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        PlacedSdf {
            to_grid: t.inverse(),
            to_world: *t,
            scale: t.matrix3.determinant().cbrt(),
            lo,
            hi,
            velocity: Affine3A::ZERO,
        }
    }

    /// `sdf` placed by `t` at the end of a substep of `1 / inv_h` s that began with it placed
    /// by `prev`: the velocity of each point fixed to the grid is where it is now less where it
    /// was, over the substep (`p - prev(t⁻¹(p))`, an affine field). A still field (`prev == t`)
    /// gets none, so it answers as a static one, bit for bit.
    pub fn moving(sdf: &Sdf, prev: &Affine3A, t: &Affine3A, inv_h: f32) -> PlacedSdf {
        let mut at = PlacedSdf::new(sdf, t);
        if prev != t {
            let back = *prev * at.to_grid;
            at.velocity = Affine3A::from_mat3_translation(
                (glam::Mat3::IDENTITY - glam::Mat3::from(back.matrix3)) * inv_h,
                -Vec3::from(back.translation) * inv_h,
            );
        }
        at
    }
}

/// Pushes one point out of a placed SDF: moved along the gradient by the (trilinear) depth,
/// its velocity answered as at an analytic collider, relative to the surface's where it moves.
#[inline]
pub fn collide_sdf_point(x: &mut Vec3, v: &mut Vec3, sdf: &Sdf, at: &PlacedSdf, friction: f32) {
    if !(x.cmpge(at.lo).all() && x.cmple(at.hi).all()) {
        return;
    }
    let Some((d, g)) = sdf.sample(at.to_grid.transform_point3(*x)) else {
        return;
    };
    if d >= 0.0 {
        return;
    }
    let n = at.to_world.transform_vector3(g).normalize_or(Vec3::Z);
    // The gradient of a trilinear field is not of unit length: move by the depth over the
    // gradient's length along it (a Newton step to the zero level), in world units.
    let len = g.length();
    let depth = if len > 1e-6 { -d / len } else { -d };
    *x += n * (depth * at.scale);
    *v = respond_moving(*v, at.velocity.transform_point3(*x), n, friction);
}

/// Pushes the free lanes of one row (inverse mass > 0) out of a placed SDF. The placed box is
/// tested for all eight lanes at once first (branch-free), then the distance of the lanes
/// inside it ([`penetrating_lanes`]), and only lanes inside the surface take the point's path:
/// most hair is outside a head's box or surface, and a call per point to learn that was half
/// the step's time at 1.6 million points.
#[inline]
pub fn collide_sdf_row(x: &mut L3, v: &mut L3, inv_mass: &Lane, sdf: &Sdf, at: &PlacedSdf, friction: f32) {
    let inside: [bool; W] = std::array::from_fn(|l| {
        (inv_mass[l] > 0.0)
            & (x.x[l] >= at.lo.x)
            & (x.y[l] >= at.lo.y)
            & (x.z[l] >= at.lo.z)
            & (x.x[l] <= at.hi.x)
            & (x.y[l] <= at.hi.y)
            & (x.z[l] <= at.hi.z)
    });
    if !inside.iter().fold(false, |a, &b| a | b) {
        return;
    }
    let deep = penetrating_lanes(x, &inside, sdf, at);
    for l in 0..W {
        if !deep[l] {
            continue;
        }
        let (mut p, mut u) = (x.get(l), v.get(l));
        collide_sdf_point(&mut p, &mut u, sdf, at, friction);
        x.set(l, p);
        v.set(l, u);
    }
}

/// Which of a row's lanes flagged `inside` (the placed box) are inside the surface: the
/// trilinear distance of [`Sdf::sample`] below zero, computed for the eight lanes at once with
/// the same operations in the same order (the grid frame as glam's `Affine3A` transforms a
/// point, the cell, the eight corners, the lerps), so each lane decides as the point's path
/// does (a test holds the distances to `sample`'s bits). Only these lanes take that path.
#[inline(always)]
fn penetrating_lanes(x: &L3, inside: &[bool; W], sdf: &Sdf, at: &PlacedSdf) -> [bool; W] {
    distances_lanes(x, inside, sdf, at).map(|d| d.is_some_and(|d| d < 0.0))
}

/// The trilinear distance of each lane flagged `inside` (`None` outside the grid or not
/// flagged).
#[inline(always)]
fn distances_lanes(x: &L3, inside: &[bool; W], sdf: &Sdf, at: &PlacedSdf) -> [Option<f32>; W] {
    let (m, t) = (at.to_grid.matrix3, at.to_grid.translation);
    let mut out = [None; W];
    for l in 0..W {
        if !inside[l] {
            continue;
        }
        // glam's `Affine3A::transform_point3`: ((X p.x + Y p.y) + Z p.z) + t, per component.
        let (px, py, pz) = (x.x[l], x.y[l], x.z[l]);
        let q = Vec3::new(
            ((m.x_axis.x * px + m.y_axis.x * py) + m.z_axis.x * pz) + t.x,
            ((m.x_axis.y * px + m.y_axis.y * py) + m.z_axis.y * pz) + t.y,
            ((m.x_axis.z * px + m.y_axis.z * py) + m.z_axis.z * pz) + t.z,
        );
        out[l] = sdf
            .cell_at((q - sdf.origin) / sdf.cell)
            .map(|(c, f)| super::trilinear::trilinear(&c, f).0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The trilinear sample of a linear field is the field, and its gradient the slope.
    #[test]
    fn a_linear_field_samples_exactly() {
        let s = Sdf::from_fn([5, 4, 3], Vec3::new(-1.0, 0.5, 2.0), 0.25, |p| {
            2.0 * p.x - p.y + 0.5 * p.z
        });
        for p in [
            Vec3::new(-0.9, 0.6, 2.1),
            Vec3::new(0.0, 1.25, 2.5),
            Vec3::new(-1.0, 0.5, 2.0),
        ] {
            let (d, g) = s.sample(p).unwrap();
            assert!((d - (2.0 * p.x - p.y + 0.5 * p.z)).abs() < 1e-5, "{p}: {d}");
            assert!((g - Vec3::new(2.0, -1.0, 0.5)).length() < 1e-4, "{p}: {g}");
        }
        assert!(s.sample(Vec3::new(-1.01, 0.6, 2.1)).is_none());
        assert!(s.sample(Vec3::new(0.01, 0.6, 2.1)).is_none());
    }

    /// The lanes' distances are the point path's, bit for bit: a turned, scaled, moved grid,
    /// points inside and outside it.
    #[test]
    fn lane_distances_equal_the_point_path() {
        let s = Sdf::from_fn([9, 7, 8], Vec3::new(-0.2, -0.15, -0.1), 0.05, |p| p.length() - 0.12);
        let t = Affine3A::from_scale_rotation_translation(
            Vec3::splat(1.3),
            glam::Quat::from_rotation_y(0.7) * glam::Quat::from_rotation_x(-0.4),
            Vec3::new(0.1, -0.3, 0.05),
        );
        let at = PlacedSdf::new(&s, &t);
        let mut rng = crate::scenes::Lcg(4);
        for _ in 0..500 {
            let mut x = L3::ZERO;
            for l in 0..W {
                let p = Vec3::new(rng.next_f32() - 0.4, rng.next_f32() - 0.8, rng.next_f32() - 0.45) * 0.7;
                x.set(l, p);
            }
            let inside = [true; W];
            let got = distances_lanes(&x, &inside, &s, &at);
            for (l, d) in got.iter().enumerate() {
                let want = s
                    .sample(at.to_grid.transform_point3(x.get(l)))
                    .map(|(d, _)| d.to_bits());
                assert_eq!(d.map(f32::to_bits), want, "lane {l} at {}", x.get(l));
            }
        }
    }
}
