//! Which integrator a scene runs: [`Integrator::AUTO`] resolved once, for both backends.

use crate::groom::Groom;
use crate::params::{Integrator, SimParams};

/// Resolves [`Integrator::AUTO`]: symplectic Euler when it is stable with a 10% margin at
/// every free point (its own mass and stiffest springs) at the substep of a 60 Hz frame, else
/// implicit Euler.
pub fn resolve_integrator(p: &SimParams, groom: &Groom) -> Integrator {
    if p.integrator != Integrator::AUTO {
        return p.integrator;
    }
    let h = 1.0 / (60.0 * p.substeps as f32);
    let springs = super::springs::point_springs(groom, p);
    if super::springs::explicit_limit_max(groom, &springs, h) < 0.9 * 4.0 {
        Integrator::SYMPLECTIC_EULER
    } else {
        Integrator::IMPLICIT_EULER
    }
}
