//! Which integrator a scene runs: [`Integrator::AUTO`] resolved once, for both backends.

use crate::groom::Groom;
use crate::params::{Integrator, SimParams};

/// Resolves [`Integrator::AUTO`]: symplectic Euler when it is stable with a 10% margin for the
/// lightest free point at the substep of a 60 Hz frame, else implicit Euler.
pub fn resolve_integrator(p: &SimParams, groom: &Groom) -> Integrator {
    if p.integrator != Integrator::AUTO {
        return p.integrator;
    }
    let min_mass = groom
        .masses()
        .iter()
        .zip(groom.pinned())
        .filter(|(_, &pin)| !pin)
        .map(|(&m, _)| m)
        .fold(f32::INFINITY, f32::min);
    let h = 1.0 / (60.0 * p.substeps as f32);
    if crate::params::explicit_limit(p, min_mass, h) < 0.9 * 4.0 {
        Integrator::SYMPLECTIC_EULER
    } else {
        Integrator::IMPLICIT_EULER
    }
}
