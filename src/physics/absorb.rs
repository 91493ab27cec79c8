//! Absorption's side of the adhesion gather (docs/WET_MODEL.md §2): while eq. 2 visits a
//! particle from a row of hair points, each lane within `r_max` asks the particle for water
//! (`wet::absorb_demand`), and the particle's pull scales with the water it still holds. The
//! demands are kept as a list and granted after every block has run (`cpu/water.rs`
//! `Water::absorb`), so what a particle gives does not depend on which thread found it.

use super::lanes::{Lane, W};
use super::wet;

/// One hair point's request to one particle in a substep.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Demand {
    /// The particle's grid slot.
    pub slot: u32,
    /// The hair point: row index (block * rows + point) times `W` plus lane.
    pub point: u32,
    /// Quanta asked for.
    pub quanta: u32,
    /// The point's room below its hold limit at the substep's start ([`wet::hold_room`]): its
    /// grant is cut to it.
    pub room: u32,
}

/// What the adhesion gather needs to absorb for one row of hair points.
pub struct WetRow<'a> {
    /// Each particle's water in grid order, quanta.
    pub mass: &'a [u32],
    /// `s / particle_mass` in N per quantum: a particle's pull is eq. 2's `s` times the
    /// fraction of a full particle it still holds.
    pub strength_per_quantum: f64,
    /// The row's water and hold limits, quanta. How full each point is (water over hold limit;
    /// a point at or above 1 asks for nothing) is computed from them at the row's first
    /// demand: most rows the gather visits have no particle within reach, and reading every
    /// visited row's water was a cache miss a row (5 % of the big groom's frame under rain).
    pub water: &'a [u32; W],
    /// The row's hold limits, quanta (`wet::hold_limit`).
    pub hold: &'a [u32; W],
    /// The length of hair each point stands for over `wet::ABSORB_LENGTH`
    /// ([`wet::absorb_share`]): its demand is in proportion.
    pub share: &'a Lane,
    /// How full each point is once computed: `None` until the row's first demand.
    pub sat: Option<Lane>,
    /// The row's first point index (`row * W`).
    pub first_point: u32,
    /// The fraction of a particle a point standing for `wet::ABSORB_LENGTH` of hair takes
    /// within `r_min` this substep ([`wet::absorb_take`] of the rate and the substep).
    pub take: f32,
    /// This worker's demands, in the order found.
    pub out: &'a mut Vec<Demand>,
}

impl WetRow<'_> {
    /// Eq. 2's strength for the particle in `slot`.
    #[inline(always)]
    pub fn strength(&self, slot: u32) -> f32 {
        (self.mass[slot as usize] as f64 * self.strength_per_quantum) as f32
    }

    /// Records each included lane's demand on the particle in `slot` (`d2s`: squared distances
    /// per lane; `inside[l]`: 1 when lane `l` is included and within `r_max`).
    #[inline(always)]
    pub fn demand(&mut self, slot: u32, d2s: &Lane, inside: &Lane, r_min: f32, r_max: f32) {
        let q = self.mass[slot as usize];
        if q == 0 {
            return;
        }
        let (water, hold) = (self.water, self.hold);
        // Written out, not `get_or_insert_with`: its closure was left a call compiled without
        // AVX2.
        let sat = match self.sat {
            Some(s) => s,
            None => {
                let s = wet::saturation_lanes(water, hold);
                self.sat = Some(s);
                s
            }
        };
        for l in 0..W {
            if inside[l] == 0.0 || sat[l] >= 1.0 {
                continue;
            }
            let w = wet::absorb_weight(d2s[l].sqrt(), r_min, r_max);
            let take = wet::absorb_take_at(self.take, self.share[l]);
            let quanta = wet::absorb_demand_taking(q, w, sat[l], take);
            if quanta > 0 {
                self.out.push(Demand {
                    slot,
                    point: self.first_point + l as u32,
                    quanta,
                    room: wet::hold_room(water[l], hold[l]),
                });
            }
        }
    }
}
