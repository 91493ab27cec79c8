//! The paper's integrator: symplectic (semi-implicit) Euler, `v += h (f/m + g); x += h v`,
//! for one row of `W` strands. Pinned points instead take the head-driven target position,
//! with the velocity that reaches it, so springs at the root see the head's motion.

use super::lanes::{Lane, L3, W};

/// Advances one row of free points by `h`, and moves pinned points (inverse mass 0) to `target`.
/// Returns nothing; `x`/`v` are updated in place.
#[inline(always)]
pub fn symplectic_euler_row(x: &mut L3, v: &mut L3, f: &L3, inv_mass: &Lane, target: Option<&L3>, g: [f32; 3], h: f32) {
    let inv_h = 1.0 / h;
    for l in 0..W {
        let w = inv_mass[l];
        let vx = v.x[l] + h * (f.x[l] * w + g[0]);
        let vy = v.y[l] + h * (f.y[l] * w + g[1]);
        let vz = v.z[l] + h * (f.z[l] * w + g[2]);
        let (nx, ny, nz) = (x.x[l] + h * vx, x.y[l] + h * vy, x.z[l] + h * vz);
        match target {
            Some(t) if w == 0.0 => {
                v.x[l] = (t.x[l] - x.x[l]) * inv_h;
                v.y[l] = (t.y[l] - x.y[l]) * inv_h;
                v.z[l] = (t.z[l] - x.z[l]) * inv_h;
                x.x[l] = t.x[l];
                x.y[l] = t.y[l];
                x.z[l] = t.z[l];
            }
            _ => {
                v.x[l] = vx;
                v.y[l] = vy;
                v.z[l] = vz;
                x.x[l] = nx;
                x.y[l] = ny;
                x.z[l] = nz;
            }
        }
    }
}

/// Whether a point's state has left the floats: a NaN or infinite position, or a velocity
/// whose squared speed is not finite (a finite velocity of 1e20 m/s counts: its square
/// overflows). Both backends fail a step on it and name the point's strand.
#[inline]
pub fn blown_up(x: glam::Vec3, v: glam::Vec3) -> bool {
    !(x.is_finite() && v.length_squared().is_finite())
}

/// A water particle's new velocity over a substep `h` (symplectic Euler, its drag taken
/// implicitly): `v' = (v + h (a + k w)) / (1 + h k)`, `a` the acceleration of every other force
/// (the hair's pull over its mass, and gravity), `k` its drag rate (drag over mass, 1/s) and `w`
/// the wind. Explicit drag, `v + h (a + k (w - v))`, diverges once `h k > 2`: a 1 mg drop under
/// the default drag (2 mN·s/m, `k` = 2000 /s) at a 1/240 s substep has `h k` = 8.3. This form
/// relaxes toward the wind at any `k` and gives the exact terminal velocity `w + a / k`.
#[inline]
pub fn particle_velocity(v: glam::Vec3, a: glam::Vec3, k: f32, wind: glam::Vec3, h: f32) -> glam::Vec3 {
    (v + h * (a + k * wind)) / (1.0 + h * k)
}
