//! The pass list: the passes a step runs for a scene, in order. Both backends build their
//! step from this one list (the CPU calls one function per pass, the GPU emits one WGSL call
//! per pass), and a pass the scene does not need is not in it.

use crate::params::{Integrator, SimParams, SpringModel};

/// One pass of the step, as reported by [`crate::Simulation::passes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// Find the liquid bridges between wet points of different strands over a grid of the wet
    /// hair points (once per step, before the substeps; docs/WET_MODEL.md §5).
    HairGrid,
    /// Hair-hair volume: spread the hair's mass and momentum over a grid and move each free
    /// point's velocity by density pressure and friction (once per step, before the
    /// substeps; docs/VOLUME.md).
    Volume,
    /// Rebuild the water grid (counting sort).
    WaterGrid,
    /// Linear air drag on hair points.
    Drag,
    /// Stretch springs (i, i+1).
    StretchSprings,
    /// Bend springs (i, i+2).
    BendSprings,
    /// Eq. 2 between hair points and particles (with held water, each point also asks the
    /// particles it reaches for water).
    Adhesion,
    /// Liquid bridges pull wet points of different strands together (§5).
    Cohesion,
    /// Symplectic Euler (or XPBD's prediction); pinned points follow the head.
    Integrate,
    /// Implicit Euler: springs, Jacobians and each strand's banded solve, per Newton iteration.
    ImplicitSolve,
    /// XPBD: project stretch then bend constraints.
    ProjectConstraints,
    /// Push hair out of colliders.
    Collide,
    /// Particles give the hair what it asked for (§2).
    Absorb,
    /// Integrate water particles (and collide them).
    WaterIntegrate,
    /// Held water runs along the strands (once per step; §6).
    Flow,
    /// Points above capacity shed drops (once per step; §6).
    Drip,
    /// Remove particles that left the domain (once per step).
    WaterCull,
    /// Held water evaporates (once per step; docs/WET_MODEL.md §7).
    Dry,
}

impl Pass {
    /// The pass's name, the same as the GPU entry point that mirrors it.
    pub fn name(self) -> &'static str {
        match self {
            Pass::HairGrid => "hair_grid",
            Pass::Volume => "volume",
            Pass::WaterGrid => "water_grid",
            Pass::Drag => "drag",
            Pass::StretchSprings => "stretch_springs",
            Pass::BendSprings => "bend_springs",
            Pass::Adhesion => "adhesion",
            Pass::Cohesion => "cohesion",
            Pass::Integrate => "integrate",
            Pass::ImplicitSolve => "implicit_solve",
            Pass::ProjectConstraints => "project_constraints",
            Pass::Collide => "collide",
            Pass::Absorb => "absorb",
            Pass::WaterIntegrate => "water_integrate",
            Pass::Flow => "flow",
            Pass::Drip => "drip",
            Pass::WaterCull => "water_cull",
            Pass::Dry => "dry",
        }
    }
}

/// Whether a scene has bend springs: strands of more than two points (`max_points` is the
/// longest strand's) and a bend family that is not switched off (zero k and c, given per
/// spring or as material properties).
pub fn has_bend(p: &SimParams, max_points: usize) -> bool {
    let on = match p.spring_model {
        SpringModel::PER_SPRING => p.bend.stiffness > 0.0 || p.bend.damping > 0.0,
        SpringModel::MATERIAL => p.material.bend_modulus > 0.0 || p.material.bend_damping > 0.0,
    };
    max_points > 2 && on
}

/// Whether a scene has stretch springs (a family that is not switched off).
pub fn has_stretch(p: &SimParams) -> bool {
    match p.spring_model {
        SpringModel::PER_SPRING => p.stretch.stiffness > 0.0 || p.stretch.damping > 0.0,
        SpringModel::MATERIAL => p.material.stretch_modulus > 0.0 || p.material.stretch_damping > 0.0,
    }
}

/// The passes a step runs for these parameters, in order: both backends build their step
/// from this one list. `bend`: the scene has bend springs ([`has_bend`]); `wet`: it holds
/// water now.
pub fn pass_list(p: &SimParams, integrator: Integrator, bend: bool, wet: bool) -> Vec<Pass> {
    let hw = &p.held_water;
    let mut v = Vec::new();
    if hw.bridges() {
        v.push(Pass::HairGrid);
    }
    if p.volume.enabled {
        v.push(Pass::Volume);
    }
    if wet {
        v.push(Pass::WaterGrid);
    }
    let explicit = integrator == Integrator::SYMPLECTIC_EULER;
    // The implicit solve takes drag itself (implicitly, in its inertial term).
    if p.air_drag > 0.0 && !integrator.is_implicit() {
        v.push(Pass::Drag);
    }
    if explicit && has_stretch(p) {
        v.push(Pass::StretchSprings);
    }
    if explicit && bend {
        v.push(Pass::BendSprings);
    }
    if wet {
        v.push(Pass::Adhesion);
    }
    if hw.bridges() {
        v.push(Pass::Cohesion);
    }
    v.push(if integrator.is_implicit() {
        Pass::ImplicitSolve
    } else {
        Pass::Integrate
    });
    if integrator == Integrator::XPBD {
        v.push(Pass::ProjectConstraints);
    }
    if !p.colliders.is_empty() || !p.sdfs.is_empty() {
        v.push(Pass::Collide);
    }
    if wet && hw.absorbs() {
        v.push(Pass::Absorb);
    }
    if wet {
        v.push(Pass::WaterIntegrate);
    }
    if hw.flows() {
        v.push(Pass::Flow);
    }
    if hw.drips() {
        v.push(Pass::Drip);
    }
    if hw.dries() {
        v.push(Pass::Dry);
    }
    if wet {
        v.push(Pass::WaterCull);
    }
    v
}
