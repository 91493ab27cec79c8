//! XPBD with small steps (Macklin et al. 2019): each substep predicts positions from the
//! explicit forces (drag, adhesion, gravity), then projects every spring once as a compliant
//! distance constraint with compliance `1 / k`, stretch then bend, root to tip (Gauss-Seidel
//! along the strand, multipliers accumulated over the sweeps), and takes the velocity from the
//! displacement. Stiff springs become hard
//! constraints instead of a blow-up; spring damping is replaced by XPBD's own dissipation.

use super::lanes::{Lane, L3, W};
use super::spring::{SpringLanes, MIN_LENGTH};

#[allow(clippy::too_many_arguments)]
/// Predicts positions: `v += h (f w + g); x += h v` for free lanes; pinned lanes jump to the
/// target. `prev` receives the positions before the step.
#[inline(always)]
pub fn predict_row(
    x: &mut L3,
    v: &mut L3,
    prev: &mut L3,
    f: &L3,
    inv_mass: &Lane,
    target: Option<&L3>,
    g: [f32; 3],
    h: f32,
) {
    *prev = *x;
    for l in 0..W {
        let w = inv_mass[l];
        v.x[l] += h * (f.x[l] * w + g[0]);
        v.y[l] += h * (f.y[l] * w + g[1]);
        v.z[l] += h * (f.z[l] * w + g[2]);
        let t = target.filter(|_| w == 0.0);
        x.x[l] = t.map_or(x.x[l] + h * v.x[l], |t| t.x[l]);
        x.y[l] = t.map_or(x.y[l] + h * v.y[l], |t| t.y[l]);
        x.z[l] = t.map_or(x.z[l] + h * v.z[l], |t| t.z[l]);
    }
}

/// Projects one spring between rows `a` and `b` as a compliant distance constraint;
/// `lambda` is its accumulated Lagrange multiplier over this substep's sweeps (zero at the
/// start of the substep), which is what makes several sweeps converge to the compliant answer.
#[inline(always)]
pub fn project(xa: &mut L3, xb: &mut L3, wa: &Lane, wb: &Lane, s: &SpringLanes, lambda: &mut Lane, h: f32) {
    for l in 0..W {
        let (dx, dy, dz) = (xb.x[l] - xa.x[l], xb.y[l] - xa.y[l], xb.z[l] - xa.z[l]);
        let len = (dx * dx + dy * dy + dz * dz).sqrt();
        // Compliance α̃ = 1 / (k h²); k = 0 disables the constraint.
        let on = s.k[l] > 0.0 && len > MIN_LENGTH;
        let alpha = if s.k[l] > 0.0 { 1.0 / (s.k[l] * h * h) } else { 0.0 };
        let wsum = wa[l] + wb[l] + alpha;
        let dl = if on && wsum > 0.0 {
            (-(len - s.rest[l]) - alpha * lambda[l]) / wsum
        } else {
            0.0
        };
        lambda[l] += dl;
        let inv = if on { 1.0 / len } else { 0.0 };
        let (nx, ny, nz) = (dx * inv * dl, dy * inv * dl, dz * inv * dl);
        xa.x[l] -= wa[l] * nx;
        xa.y[l] -= wa[l] * ny;
        xa.z[l] -= wa[l] * nz;
        xb.x[l] += wb[l] * nx;
        xb.y[l] += wb[l] * ny;
        xb.z[l] += wb[l] * nz;
    }
}

/// Velocity from the step's displacement: `v = (x - prev) / h`.
#[inline(always)]
pub fn finish_row(x: &L3, v: &mut L3, prev: &L3, h: f32) {
    let inv_h = 1.0 / h;
    for l in 0..W {
        v.x[l] = (x.x[l] - prev.x[l]) * inv_h;
        v.y[l] = (x.y[l] - prev.y[l]) * inv_h;
        v.z[l] = (x.z[l] - prev.z[l]) * inv_h;
    }
}
