//! Which integrator a scene runs: [`Integrator::AUTO`] resolved at create, for both backends,
//! and the stability bound the error budget's AUTO choice keeps symplectic Euler within.

use crate::groom::Groom;
use crate::params::{Integrator, SimParams};

/// Symplectic Euler counts as stable while `h² λ + 2 h γ` ([`crate::params::explicit_limit`])
/// stays under this: the bound 4 with a 10% margin.
pub const EXPLICIT_MARGIN: f32 = 0.9 * 4.0;

/// Resolves [`Integrator::AUTO`]: symplectic Euler when it is stable with a 10% margin at
/// every free point (its own mass, stiffest springs and air drag) at the substep of a 60 Hz
/// frame, else implicit Euler, or BDF2 under an error budget ([`SimParams::tolerance`]: the
/// budget watches the error, and BDF2 is the more accurate at the same cost).
pub fn resolve_integrator(p: &SimParams, groom: &Groom) -> Integrator {
    if p.integrator != Integrator::AUTO {
        return p.integrator;
    }
    let h = 1.0 / (60.0 * p.substeps as f32);
    let springs = super::springs::point_springs(groom, p);
    if super::springs::explicit_limit_max(groom, &springs, p.hair_drag(), h) < EXPLICIT_MARGIN {
        Integrator::SYMPLECTIC_EULER
    } else if p.tolerance > 0.0 {
        Integrator::BDF2
    } else {
        Integrator::IMPLICIT_EULER
    }
}

/// The longest substep at which symplectic Euler is stable on `groom` under `p`, s (the root
/// of `h² λ + 2 h γ = EXPLICIT_MARGIN` with the groom's largest rates; infinite without
/// springs). Its largest rates may come from different points, so this errs short.
pub fn explicit_max_substep(p: &SimParams, groom: &Groom) -> f32 {
    let springs = super::springs::point_springs(groom, p);
    let (l, g) = super::springs::explicit_rates_max(groom, &springs, p.hair_drag());
    if l <= 0.0 {
        return if g > 0.0 {
            EXPLICIT_MARGIN / (2.0 * g)
        } else {
            f32::INFINITY
        };
    }
    // The stable root of λ h² + 2 γ h - M = 0, written so it does not cancel when γ² ≫ λ M.
    EXPLICIT_MARGIN / (g + (g * g + l * EXPLICIT_MARGIN).sqrt())
}
