//! Water rules both backends apply: the domain particles are culled outside of, the checks
//! on particles a host adds, and the bound eq. 2's stability limit starts from.

use crate::error::{invalid, Result};
use crate::groom::Groom;
use crate::params::SimParams;
use glam::Vec3;

/// The sphere, in head space, outside of which particles are removed at the end of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterDomain {
    /// Centre in head space (the groom's bounding-box centre); the head transform places it.
    pub center_local: Vec3,
    /// Radius, m: `params.water.domain_radius`, or when that is 0, half the groom's diagonal
    /// plus its longest strand.
    pub radius: f32,
}

impl WaterDomain {
    /// The domain of `groom` under `params`.
    pub fn new(groom: &Groom, params: &SimParams) -> Self {
        let (lo, hi) = groom.bounds();
        let radius = if params.water.domain_radius > 0.0 {
            params.water.domain_radius
        } else {
            0.5 * (hi - lo).length() + groom.max_strand_length()
        };
        WaterDomain {
            center_local: 0.5 * (lo + hi),
            radius,
        }
    }
}

/// Checks particles a host adds (both backends): finite positions and velocities, and as
/// many velocities as positions (or none).
pub fn check_new_particles(pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
    if !vel.is_empty() && vel.len() != pos.len() {
        return Err(invalid!("{} velocities for {} particles", vel.len(), pos.len()));
    }
    if let Some(i) = pos.iter().position(|p| !p.is_finite()) {
        return Err(invalid!("water position {i} is not finite: {:?}", pos[i]));
    }
    if let Some(i) = vel.iter().position(|v| !v.is_finite()) {
        return Err(invalid!("water velocity {i} is not finite: {:?}", vel[i]));
    }
    Ok(())
}

/// The largest share of eq. 2's pull times inverse mass of any free point of `groom` under
/// `params`: what `physics::pull_limit::PullLimit::new` bounds a row's stiffness with, the
/// same for both backends (held water only makes points heavier, so the dry groom bounds it).
pub fn pull_weight_max(params: &SimParams, groom: &Groom) -> f32 {
    let share = params.adhesion_share();
    let rest = super::springs::rest_lengths(groom);
    let mut most = 0.0f32;
    for s in 0..groom.strand_count() {
        let r = groom.strand_range(s);
        for i in r.clone().filter(|&i| !groom.pinned()[i]) {
            let before = if i > r.start { rest[i - 1][0] } else { 0.0 };
            most = most.max(share.at(before, rest[i][0]) / groom.masses()[i]);
        }
    }
    most
}
