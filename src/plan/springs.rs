//! The springs' rest lengths and constants, taken from the groom's rest pose once: the CPU
//! layout, the GPU's point records, the energy diagnostic and the f64 reference all read
//! these numbers, so both backends start from the same bits.

use crate::groom::Groom;
use crate::params::{SimParams, SpringModel, SpringParams, MIN_MATERIAL_LENGTH};
use crate::physics::per_length::PerLength;

/// Per point, in the host's order: the rest length to the next point (stretch) and to the
/// point after next (bend), 0 where the strand has no such point. Computed in f32 from the f32
/// rest pose.
pub fn rest_lengths(g: &Groom) -> Vec<[f32; 2]> {
    let pos = g.positions();
    let mut rest = vec![[0.0; 2]; pos.len()];
    for s in 0..g.strand_count() {
        let r = g.strand_range(s);
        for i in r.clone() {
            if i + 1 < r.end {
                rest[i][0] = (pos[i + 1] - pos[i]).length();
            }
            if i + 2 < r.end {
                rest[i][1] = (pos[i + 2] - pos[i]).length();
            }
        }
    }
    rest
}

/// The stretch spring of rest length `rest`, by the scene's spring model: the family's k and c
/// as given, or `EA / l` and `C / l` from the material (l floored at [`MIN_MATERIAL_LENGTH`]).
pub fn stretch_spring(p: &SimParams, rest: f32) -> SpringParams {
    match p.spring_model {
        SpringModel::PER_SPRING => p.stretch,
        SpringModel::MATERIAL => {
            let l = rest.max(MIN_MATERIAL_LENGTH);
            SpringParams {
                stiffness: p.material.stretch_modulus / l,
                damping: p.material.stretch_damping / l,
            }
        }
    }
}

/// The bend spring of rest span `rest`: the family's k and c, or `EI / L³` and `C / L³` from
/// the material (L floored at twice [`MIN_MATERIAL_LENGTH`]).
pub fn bend_spring(p: &SimParams, rest: f32) -> SpringParams {
    match p.spring_model {
        SpringModel::PER_SPRING => p.bend,
        SpringModel::MATERIAL => {
            let l = rest.max(2.0 * MIN_MATERIAL_LENGTH);
            let l3 = l * l * l;
            SpringParams {
                stiffness: p.material.bend_modulus / l3,
                damping: p.material.bend_damping / l3,
            }
        }
    }
}

/// One point's two springs: to the next point and to the point after next.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointSprings {
    /// Rest lengths (stretch, bend), m; 0 where the strand has no such point.
    pub rest: [f32; 2],
    /// The stretch spring (zero where none).
    pub stretch: SpringParams,
    /// The bend spring (zero where none).
    pub bend: SpringParams,
}

/// Every point's springs, in the host's order.
pub fn point_springs(g: &Groom, p: &SimParams) -> Vec<PointSprings> {
    let rest = rest_lengths(g);
    let mut out = vec![PointSprings::default(); rest.len()];
    for s in 0..g.strand_count() {
        let r = g.strand_range(s);
        for i in r.clone() {
            let o = &mut out[i];
            o.rest = rest[i];
            if i + 1 < r.end {
                o.stretch = stretch_spring(p, rest[i][0]);
            }
            if i + 2 < r.end {
                o.bend = bend_spring(p, rest[i][1]);
            }
        }
    }
    out
}

/// The largest [`crate::params::explicit_limit`] over the groom's free points for substep `h`:
/// each point with the stiffest stretch and bend spring it touches, and its air drag on its
/// mass.
pub fn explicit_limit_max(g: &Groom, springs: &[PointSprings], drag: PerLength, h: f32) -> f32 {
    point_rates(g, springs, drag).fold(0.0f32, |worst, (l, c)| worst.max(h * h * l + 2.0 * h * c))
}

/// The largest stiffness and damping rates ([`crate::params::explicit_rates`], the damping
/// with the air drag's `c / m`) over the groom's free points, each on its own:
/// `h² λ + 2 h γ` with these bounds every point's [`crate::params::explicit_limit`] at any `h`.
pub fn explicit_rates_max(g: &Groom, springs: &[PointSprings], drag: PerLength) -> (f32, f32) {
    point_rates(g, springs, drag).fold((0.0f32, 0.0f32), |(a, b), (l, c)| (a.max(l), b.max(c)))
}

/// Each free point's rates, with the stiffest stretch and bend spring it touches, and its air
/// drag: symplectic Euler takes the drag explicitly too, and a light point under a strong drag
/// (`h c / m` > 2) diverges as a stiff spring does.
fn point_rates<'a>(
    g: &'a Groom,
    springs: &'a [PointSprings],
    drag: PerLength,
) -> impl Iterator<Item = (f32, f32)> + 'a {
    (0..g.strand_count()).flat_map(move |s| {
        let r = g.strand_range(s);
        r.clone().filter(|&i| !g.pinned()[i]).map(move |i| {
            let (mut st, mut bd) = (SpringParams::default(), SpringParams::default());
            let take = |into: &mut SpringParams, sp: SpringParams| {
                into.stiffness = into.stiffness.max(sp.stiffness);
                into.damping = into.damping.max(sp.damping);
            };
            take(&mut st, springs[i].stretch);
            let mut before = 0.0;
            if i > r.start {
                take(&mut st, springs[i - 1].stretch);
                before = springs[i - 1].rest[0];
            }
            take(&mut bd, springs[i].bend);
            if i >= r.start + 2 {
                take(&mut bd, springs[i - 2].bend);
            }
            let (l, c) = crate::params::explicit_rates(st, bd, g.masses()[i]);
            (l, c + drag.at(before, springs[i].rest[0]) / g.masses()[i])
        })
    })
}
