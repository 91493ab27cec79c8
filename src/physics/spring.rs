//! Eq. 1: the spring-damper between two points, for `W` strands at once.
//!
//! `f_a = k (|d| - l) d̂ + damping`, `f_b = -f_a`, `d = x_b - x_a`. The paper damps the whole
//! relative velocity (`c (v_b - v_a)`), which also damps rigid swinging; the axial form
//! (`c ((v_b - v_a)·d̂) d̂`) damps only stretching, as Warp, Newton and the peers' scene do.

use super::lanes::{Lane, L3, W};

/// Which relative velocity a spring damper acts on (`WetHairSimDesc::damping_model`);
/// exported as `WetHairDampingModel`.
/// cbindgen:rename-all=prefix:WETHAIR_DAMPING_
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
#[allow(non_camel_case_types)]
pub enum DampingModel {
    /// The paper's form: `c (v_b - v_a)`, the whole relative velocity.
    RELATIVE = 0,
    /// Along the spring only: `c ((v_b - v_a)·d̂) d̂` (the peers' scene uses this).
    AXIAL = 1,
}

/// Segments shorter than this have no defined direction: the spring exerts no force rather
/// than divide by ~0 (real grooms carry near-degenerate segments).
pub const MIN_LENGTH: f32 = 1.0e-12;

/// Per-lane spring constants: rest length, damping (N·s/m) and stiffness (N/m). Stiffness
/// last: in [`super::lanes::ParamRow`] the bend spring's stiffness then sits next to the
/// inverse mass, the two fields held water rewrites each step (`repr(C)`, and a compile-time
/// check there, hold the order).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct SpringLanes {
    /// Rest length, m.
    pub rest: Lane,
    /// Damping, N·s/m.
    pub c: Lane,
    /// Stiffness, N/m (0 disables the spring in that lane).
    pub k: Lane,
}

/// Adds eq. 1's force to `fa` (on point a) and subtracts it from `fb` (on point b).
#[inline(always)]
pub fn spring<const AXIAL: bool>(xa: &L3, xb: &L3, va: &L3, vb: &L3, s: &SpringLanes, fa: &mut L3, fb: &mut L3) {
    for l in 0..W {
        let dx = xb.x[l] - xa.x[l];
        let dy = xb.y[l] - xa.y[l];
        let dz = xb.z[l] - xa.z[l];
        let len = (dx * dx + dy * dy + dz * dz).sqrt();
        let inv = if len > MIN_LENGTH { 1.0 / len } else { 0.0 };
        let (nx, ny, nz) = (dx * inv, dy * inv, dz * inv);
        let dvx = vb.x[l] - va.x[l];
        let dvy = vb.y[l] - va.y[l];
        let dvz = vb.z[l] - va.z[l];
        let (gx, gy, gz) = if AXIAL {
            let m = s.k[l] * (len - s.rest[l]) + s.c[l] * (dvx * nx + dvy * ny + dvz * nz);
            (m * nx, m * ny, m * nz)
        } else {
            let m = s.k[l] * (len - s.rest[l]);
            (m * nx + s.c[l] * dvx, m * ny + s.c[l] * dvy, m * nz + s.c[l] * dvz)
        };
        fa.x[l] += gx;
        fa.y[l] += gy;
        fa.z[l] += gz;
        fb.x[l] -= gx;
        fb.y[l] -= gy;
        fb.z[l] -= gz;
    }
}

/// Potential energy of one spring (J), for diagnostics.
pub fn spring_energy(k: f32, rest: f32, len: f32) -> f64 {
    0.5 * k as f64 * ((len - rest) as f64).powi(2)
}
