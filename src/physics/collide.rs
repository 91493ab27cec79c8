//! Sphere and capsule colliders. A point found inside is moved to the surface, loses the
//! velocity component into the surface, and its tangential velocity is scaled by
//! `1 - friction`, both relative to the surface where it moves (`Placed::va`, `vab`: a collider
//! moving with the head or a bone carries what rests on it). Colliders are given in head space
//! and follow the head transform, or, in a scene with collider frames
//! (`SimParams::collider_frames`), each in its own frame (a bone's) that the host moves every
//! step ([`ColliderFrames`]).

use super::head::HeadPath;
use super::lanes::{Lane, L3, W};
use glam::{Affine3A, Vec3};

/// Squared distance from the axis below which a point counts as on it: its push-out normal is
/// then +z (no direction can be taken from the offset).
pub const ON_AXIS_D2: f32 = 1e-24;

/// A collider shape in head space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere: centre and radius (m).
    Sphere {
        /// Centre, head space.
        center: Vec3,
        /// Radius, m.
        radius: f32,
    },
    /// A capsule: the points within `radius` of the segment `a`–`b`.
    Capsule {
        /// First end of the axis, head space.
        a: Vec3,
        /// Second end of the axis, head space.
        b: Vec3,
        /// Radius, m.
        radius: f32,
    },
}

/// A collider placed in world space for one substep: a capsule (a sphere has `a == b`), and
/// how fast it moves there.
#[derive(Clone, Copy, Debug, Default)]
pub struct Placed {
    /// Axis start.
    pub a: Vec3,
    /// Axis end minus start.
    pub ab: Vec3,
    /// `1 / |ab|²`, or 0 for a sphere.
    pub inv_len2: f32,
    /// Radius in world units.
    pub radius: f32,
    /// Velocity of the axis start over the substep, m/s (0 where it stands still).
    pub va: Vec3,
    /// Rate of change of `ab` over the substep, 1/s: the axis point at `t` moves at
    /// `va + vab t`.
    pub vab: Vec3,
}

impl Placed {
    /// This placement moving from `prev` (the same shape at the substep's start) over a
    /// substep of `1 / inv_h` s: its axis's velocities. Where the two are equal they are 0
    /// exactly, and a still collider answers as a static one, bit for bit.
    #[inline]
    pub fn moving_from(self, prev: &Placed, inv_h: f32) -> Placed {
        Placed {
            va: (self.a - prev.a) * inv_h,
            vab: (self.ab - prev.ab) * inv_h,
            ..self
        }
    }
}

impl Shape {
    /// Places the shape with the head transform; radii scale by the transform's mean scale.
    pub fn place(&self, head: &Affine3A) -> Placed {
        let scale = head.matrix3.determinant().abs().cbrt();
        let (a, b, r) = match *self {
            Shape::Sphere { center, radius } => (center, center, radius),
            Shape::Capsule { a, b, radius } => (a, b, radius),
        };
        let (a, b) = (head.transform_point3(a), head.transform_point3(b));
        let ab = b - a;
        let l2 = ab.length_squared();
        Placed {
            a,
            ab,
            inv_len2: if l2 > 0.0 { 1.0 / l2 } else { 0.0 },
            radius: r * scale,
            va: Vec3::ZERO,
            vab: Vec3::ZERO,
        }
    }
}

/// Where the analytic colliders are over a step, for both backends: each on the head, or, in a
/// scene with collider frames, each on its own frame moved from `from` to `to` over the step's
/// substeps as the head moves ([`HeadPath`], the same fractions and bits). Empty: they follow
/// the head (no frame is kept, no interpolation runs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColliderFrames {
    /// Each collider's path over the next step (taken apart once a step, not each substep).
    paths: Vec<HeadPath>,
}

impl ColliderFrames {
    /// The colliders' frames at rest at `start` (one per collider; empty: on the head).
    pub fn new(start: &[Affine3A]) -> Self {
        ColliderFrames {
            paths: start.iter().map(|t| HeadPath::new(t, t)).collect(),
        }
    }

    /// The next step moves each collider's frame from `from` to `to` (as many as at `new`;
    /// no allocation).
    pub fn set(&mut self, from: &[Affine3A], to: &[Affine3A]) {
        debug_assert!(from.len() == self.paths.len() && to.len() == self.paths.len());
        for ((p, f), t) in self.paths.iter_mut().zip(from).zip(to) {
            *p = HeadPath::new(f, t);
        }
    }

    /// Collider `c` (`shape`) placed at the end of substep `s` of `n` (of `1 / inv_h` s),
    /// moving from where it was at the substep's start: the head at `heads[0]` then, at
    /// `heads[1]` at its end.
    #[inline]
    pub fn place(&self, c: usize, shape: &Shape, heads: [&Affine3A; 2], s: usize, n: usize, inv_h: f32) -> Placed {
        let (t0, t1) = match self.paths.get(c) {
            Some(p) => (p.at(s as f32 / n as f32), p.at((s + 1) as f32 / n as f32)),
            None => (*heads[0], *heads[1]),
        };
        shape.place(&t1).moving_from(&shape.place(&t0), inv_h)
    }

    /// Places every collider of `shapes` for each of the step's substeps of `1 / inv_h` s into
    /// `out` (`heads.len()` substeps of `shapes.len()`, substep after substep): the head at
    /// `from` at the step's start and at `heads[s]` at the end of substep `s`.
    pub fn place_substeps(
        &self,
        shapes: &[Shape],
        from: &Affine3A,
        heads: &[Affine3A],
        inv_h: f32,
        out: &mut [Placed],
    ) {
        let (n, nc) = (heads.len(), shapes.len());
        for s in 0..n {
            let start = if s == 0 { from } else { &heads[s - 1] };
            for (c, shape) in shapes.iter().enumerate() {
                out[s * nc + c] = self.place(c, shape, [start, &heads[s]], s, n, inv_h);
            }
        }
    }
}

/// Pushes the free lanes of one row (inverse mass > 0) out of a placed collider: the same
/// response as [`collide_point`], computed on all lanes with selects so that it vectorises
/// (hair resting on a head touches it on most rows, every substep).
#[inline(always)]
pub fn collide_row(x: &mut L3, v: &mut L3, inv_mass: &Lane, c: &Placed, friction: f32) {
    let r2 = c.radius * c.radius;
    // Cheap test first (no sqrt, no division): most rows of a groom touch no collider.
    let mut any = 0u32;
    for l in 0..W {
        let (px, py, pz) = (x.x[l] - c.a.x, x.y[l] - c.a.y, x.z[l] - c.a.z);
        let t = ((px * c.ab.x + py * c.ab.y + pz * c.ab.z) * c.inv_len2).clamp(0.0, 1.0);
        let (dx, dy, dz) = (px - c.ab.x * t, py - c.ab.y * t, pz - c.ab.z * t);
        any |= ((dx * dx + dy * dy + dz * dz < r2) & (inv_mass[l] > 0.0)) as u32;
    }
    if any == 0 {
        return;
    }
    for l in 0..W {
        let (px, py, pz) = (x.x[l] - c.a.x, x.y[l] - c.a.y, x.z[l] - c.a.z);
        let t = ((px * c.ab.x + py * c.ab.y + pz * c.ab.z) * c.inv_len2).clamp(0.0, 1.0);
        let (ax, ay, az) = (c.a.x + c.ab.x * t, c.a.y + c.ab.y * t, c.a.z + c.ab.z * t);
        let (dx, dy, dz) = (x.x[l] - ax, x.y[l] - ay, x.z[l] - az);
        let d2 = dx * dx + dy * dy + dz * dz;
        let inside = (d2 < r2) & (inv_mass[l] > 0.0);
        // On the axis there is no way out: push along +z, as collide_point does.
        let on_axis = d2 <= ON_AXIS_D2;
        let inv = if on_axis { 0.0 } else { 1.0 / d2.sqrt() };
        let (nx, ny, nz) = if on_axis {
            (0.0, 0.0, 1.0)
        } else {
            (dx * inv, dy * inv, dz * inv)
        };
        // The surface's velocity where the point touches it (the axis point's), and the
        // point's velocity relative to it, which the response takes (`respond_moving`).
        let (cx, cy, cz) = (c.va.x + c.vab.x * t, c.va.y + c.vab.y * t, c.va.z + c.vab.z * t);
        let (vx, vy, vz) = (v.x[l] - cx, v.y[l] - cy, v.z[l] - cz);
        let vn = vx * nx + vy * ny + vz * nz;
        let into = vn.min(0.0);
        let (tx, ty, tz) = (vx - nx * vn, vy - ny * vn, vz - nz * vn);
        // Unconditional stores of selected values: the form LLVM vectorises.
        x.x[l] = if inside { ax + nx * c.radius } else { x.x[l] };
        x.y[l] = if inside { ay + ny * c.radius } else { x.y[l] };
        x.z[l] = if inside { az + nz * c.radius } else { x.z[l] };
        v.x[l] = if inside {
            cx + (vx - nx * into - tx * friction)
        } else {
            v.x[l]
        };
        v.y[l] = if inside {
            cy + (vy - ny * into - ty * friction)
        } else {
            v.y[l]
        };
        v.z[l] = if inside {
            cz + (vz - nz * into - tz * friction)
        } else {
            v.z[l]
        };
    }
}

/// One substep's colliders as placed: the analytic ones and the SDFs with their placements
/// (one per SDF).
#[derive(Clone, Copy, Debug)]
pub struct Colliders<'a> {
    /// Spheres and capsules.
    pub placed: &'a [Placed],
    /// The SDF grids.
    pub sdfs: &'a [std::sync::Arc<super::sdf::Sdf>],
    /// Where each SDF is this substep.
    pub placed_sdfs: &'a [super::sdf::PlacedSdf],
}

impl Colliders<'_> {
    /// Pushes one point (a water particle) out of every collider, analytic ones first.
    #[inline]
    pub fn push_out_point(&self, x: &mut Vec3, v: &mut Vec3, friction: f32) {
        for c in self.placed {
            collide_point(x, v, c, friction);
        }
        for (sdf, at) in self.sdfs.iter().zip(self.placed_sdfs) {
            super::sdf::collide_sdf_point(x, v, sdf, at, friction);
        }
    }

    /// Whether there is any collider to push out of.
    #[inline(always)]
    pub fn any(&self) -> bool {
        !self.placed.is_empty() || !self.sdfs.is_empty()
    }

    /// Pushes the free lanes of one row out of every collider, analytic ones first. Always
    /// inlined: the row kernels call it from their AVX2 bodies, and a call out of them runs the
    /// analytic colliders without AVX2 (the head collider was then 57% of a dry paper-scene step).
    #[inline(always)]
    pub fn push_out_row(&self, x: &mut L3, v: &mut L3, inv_mass: &Lane, friction: f32) {
        for c in self.placed {
            collide_row(x, v, inv_mass, c, friction);
        }
        for (sdf, at) in self.sdfs.iter().zip(self.placed_sdfs) {
            super::sdf::collide_sdf_row(x, v, inv_mass, sdf, at, friction);
        }
    }
}

/// Pushes one point (a water particle) out of a placed collider.
#[inline(always)]
pub fn collide_point(x: &mut Vec3, v: &mut Vec3, c: &Placed, friction: f32) {
    let (inside, q, n, t) = closest(c, *x);
    if inside {
        *x = q;
        *v = respond_moving(*v, c.va + c.vab * t, n, friction);
    }
}

/// Whether `p` is inside, the surface point to move it to, the outward normal, and where
/// along the axis it is (0..=1).
#[inline(always)]
fn closest(c: &Placed, p: Vec3) -> (bool, Vec3, Vec3, f32) {
    let t = ((p - c.a).dot(c.ab) * c.inv_len2).clamp(0.0, 1.0);
    let axis = c.a + c.ab * t;
    let d = p - axis;
    let d2 = d.length_squared();
    if d2 >= c.radius * c.radius {
        return (false, p, Vec3::ZERO, t);
    }
    // A point exactly on the axis has no direction out: push it along +z (up), a fixed choice.
    let n = if d2 > ON_AXIS_D2 { d / d2.sqrt() } else { Vec3::Z };
    (true, axis + n * c.radius, n, t)
}

/// [`respond`] against a surface moving at `surface` m/s: the velocity relative to it loses
/// its part into the surface and the friction's share of the rest, so a point resting on a
/// moving shoulder is carried along, and one struck is pushed at least at the surface's speed.
/// A still surface (`surface` 0) answers as `respond` does.
#[inline(always)]
pub(crate) fn respond_moving(v: Vec3, surface: Vec3, n: Vec3, friction: f32) -> Vec3 {
    surface + respond(v - surface, n, friction)
}

/// Removes the velocity into the surface and applies friction to the rest.
#[inline(always)]
pub(crate) fn respond(v: Vec3, n: Vec3, friction: f32) -> Vec3 {
    let vn = v.dot(n);
    let normal = if vn < 0.0 { n * vn } else { Vec3::ZERO };
    let tangential = v - n * vn;
    (v - normal) - tangential * friction
}
