//! The live error estimate ([`SimParams::error_estimate_stride`]).
//!
//! A shadow simulation runs every N-th strand again, on the CPU at twice the substeps, from
//! the same rest pose under the same head transforms, wind and soaking. If the simulation's
//! position error after time t is `C h^p` (h its substep, p its integrator's order), the
//! shadow's is `C (h/2)^p`, and their difference `d` gives the simulation's own error as
//! `d 2^p / (2^p - 1)` (Richardson): `2 d` for the first-order integrators, `4 d / 3` for BDF2.
//! It estimates the error the positions carry now, accumulated since the start, which is what a
//! host asking "how far off is this frame" wants; a dissipative groom forgets old errors, so it
//! follows the current substep's accuracy within a second or so.
//!
//! Strands run alone in the shadow, so it is exact only while strands do not act on one
//! another: water particles (the host's, rain, spray, drips that reach other strands) and
//! liquid bridges couple them, and the estimate is then withheld until a reset (the wet
//! scenes are chaotic anyway: docs/METHOD.md §3). The shadow runs on the CPU whatever the
//! backend, so on the GPU it also carries the backends' parity difference (f32 solves there).

use super::Simulation;
use crate::error::Result;
use crate::groom::Groom;
use crate::params::{Backend, Integrator, SimParams, VertexAttributes, MAX_SUBSTEPS};
use glam::{Affine3A, Vec3};

/// The estimate of the positions' error now, m ([`crate::Stats::error_estimate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorEstimate {
    /// Root mean square over the sampled strands' points (pinned points included, as the
    /// accuracy report's RMS error).
    pub rms: f32,
    /// Largest over the sampled strands' points.
    pub max: f32,
}

/// Why the shadow is not estimating now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Withheld {
    /// Water coupled strands that the shadow runs alone.
    Coupled,
    /// The shadow's own step failed (its finer substeps should not; reported, not hidden).
    Failed,
}

/// Every N-th strand, run again at twice the substeps (see the module doc).
#[derive(Debug)]
pub(super) struct Shadow {
    sim: Box<Simulation>,
    /// The simulation's strands the shadow runs: every `stride`-th.
    stride: usize,
    /// Host index of each shadow point, in the shadow's order.
    points: Vec<u32>,
    /// `2^p / (2^p - 1)` for the integrator's order p.
    richardson: f32,
    withheld: Option<Withheld>,
    /// The shadow's positions before its last step, kept when the simulation reads its own
    /// one step behind (the GPU under a budget: [`Shadow::keep_behind`]).
    behind: Option<Behind>,
}

/// The shadow's positions one step behind, and the indices that read them all.
#[derive(Debug)]
struct Behind {
    x: Vec<Vec3>,
    /// 0..points.
    all: Vec<u32>,
}

/// The order of accuracy in positions of each integrator (after AUTO is resolved).
pub(super) fn order(i: Integrator) -> i32 {
    match i {
        Integrator::BDF2 => 2,
        _ => 1,
    }
}

impl Shadow {
    /// The shadow of `groom` under `p` for an engine running `integrator`; `None` when the
    /// estimate is off or cannot be made (bridges couple every strand; the substeps cannot
    /// double past [`MAX_SUBSTEPS`]).
    pub(super) fn new(groom: &Groom, p: &SimParams, integrator: Integrator) -> Result<Option<Shadow>> {
        let stride = p.estimate_stride() as usize;
        if stride == 0 || p.held_water.bridges() || p.substeps * 2 > MAX_SUBSTEPS {
            return Ok(None);
        }
        let mut pos = Vec::new();
        let mut counts = Vec::new();
        let mut pinned = Vec::new();
        let mut mass = Vec::new();
        let mut points = Vec::new();
        for s in (0..groom.strand_count()).step_by(stride) {
            let r = groom.strand_range(s);
            counts.push(r.len() as u32);
            pos.extend_from_slice(&groom.positions()[r.clone()]);
            pinned.extend_from_slice(&groom.pinned()[r.clone()]);
            mass.extend_from_slice(&groom.masses()[r.clone()]);
            points.extend(r.map(|i| i as u32));
        }
        let sample = Groom::new(pos, &counts, Some(pinned), Some(mass), 1.0)?;
        let params = SimParams {
            substeps: p.substeps * 2,
            integrator,
            threads: 1,
            backend: Backend::CPU,
            attributes: VertexAttributes(VertexAttributes::POSITION),
            error_estimate_stride: 0,
            tolerance: 0.0,
            // The sample is of the strands the backend simulates (the guides, with guides).
            guides: crate::params::Guides::ALL,
            ..p.clone()
        };
        let sim = Simulation::new(&sample, params)?;
        let q = 2f32.powi(order(integrator));
        Ok(Some(Shadow {
            sim: Box::new(sim),
            stride,
            points,
            richardson: q / (q - 1.0),
            withheld: None,
            behind: None,
        }))
    }

    /// Steps the shadow as the simulation just stepped: by `dt` to the head transform `head`.
    pub(super) fn step(&mut self, dt: f32, head: Affine3A) {
        if self.withheld.is_some() {
            return;
        }
        if let Some(b) = &mut self.behind {
            if self.sim.engine.positions_of(&b.all, &mut b.x).is_err() {
                self.withheld = Some(Withheld::Failed);
            }
        }
        self.sim.head = head;
        if self.sim.step(dt).is_err() {
            self.withheld = Some(Withheld::Failed);
        }
    }

    /// Sets the sampled strands' root frames as the simulation's next step reaches them.
    pub(super) fn place_roots(&mut self, to: &[crate::physics::roots::RootFrame]) {
        if let Some(r) = &mut self.sim.roots {
            r.target.clear();
            r.target.extend(to.iter().step_by(self.stride).copied());
        }
    }

    /// Sets the sampled strands' root targets from the simulation's (before a reset).
    pub(super) fn set_root_targets(&mut self, roots: &super::roots::RootTargets) {
        let stride = self.stride;
        if let Some(r) = &mut self.sim.roots {
            r.target.clear();
            r.target.extend(roots.targets_every(stride));
        }
    }

    /// Places the SDF colliders as the simulation's next step does.
    pub(super) fn place_sdfs(&mut self, to: &[Affine3A]) {
        self.sim.sdf_frames.set_all(to);
    }

    /// Places the colliders' own frames as the simulation's next step does.
    pub(super) fn place_colliders(&mut self, to: &[Affine3A]) {
        self.sim.collider_frames.set_all(to);
    }

    /// Keeps the shadow's positions before each step, for [`Shadow::estimate_behind`].
    pub(super) fn keep_behind(&mut self) {
        self.behind = Some(Behind {
            x: Vec::new(),
            all: (0..self.points.len() as u32).collect(),
        });
    }

    /// Runs twice `n` substeps from the next step on, as the simulation runs `n`.
    pub(super) fn set_substeps(&mut self, n: u32) {
        self.sim.engine.set_substeps(2 * n);
    }

    /// Runs `integrator` from the next step on, as the simulation does (AUTO's choice).
    pub(super) fn set_integrator(&mut self, integrator: Integrator) {
        if self.sim.engine.set_integrator(integrator).is_err() {
            self.withheld = Some(Withheld::Failed);
        }
        let q = 2f32.powi(order(integrator));
        self.richardson = q / (q - 1.0);
    }

    /// The host indices of the sampled points (the simulation reads its positions there).
    pub(super) fn points(&self) -> &[u32] {
        &self.points
    }

    /// Whether the estimate is withheld now.
    pub(super) fn withheld(&self) -> bool {
        self.withheld.is_some()
    }

    /// Water reached the simulation: strands may act on one another from now on.
    pub(super) fn couple(&mut self) {
        self.withheld = Some(Withheld::Coupled);
    }

    /// Forwards the wind (the shadow's clock is the simulation's).
    pub(super) fn set_wind(&mut self, wind: crate::Wind) {
        let _ = self.sim.set_wind(wind); // validated by the caller
    }

    /// Forwards a soak.
    pub(super) fn soak(&mut self, s: f32) {
        if self.sim.soak(s).is_err() {
            self.withheld = Some(Withheld::Failed);
        }
    }

    /// Back to rest at `head`, estimating again.
    pub(super) fn reset(&mut self, head: Affine3A) {
        if let Some(b) = &mut self.behind {
            b.x.clear();
        }
        self.sim.head = head;
        self.withheld = self.sim.reset().err().map(|_| Withheld::Failed);
    }

    /// The estimate from the simulation's positions `x` (every point, host order), or `None`
    /// while withheld.
    pub(super) fn estimate(&self, x: &[Vec3]) -> Option<ErrorEstimate> {
        if x.is_empty() {
            return None;
        }
        self.estimate_at(self.points.iter().map(|&i| x[i as usize]))
    }

    /// The estimate from the simulation's positions at the sampled points, in order.
    pub(super) fn estimate_at(&self, x: impl Iterator<Item = Vec3>) -> Option<ErrorEstimate> {
        if self.withheld.is_some() {
            return None;
        }
        let y = self.sim.point_states().ok()?;
        self.compare(x, y.iter().map(|s| s.0))
    }

    /// The estimate one step behind: from the simulation's positions at the sampled points
    /// at the end of the step before the last, against the shadow's then.
    pub(super) fn estimate_behind(&self, x: &[Vec3]) -> Option<ErrorEstimate> {
        let y = self
            .behind
            .as_ref()
            .filter(|b| b.x.len() == x.len() && self.withheld.is_none())?;
        self.compare(x.iter().copied(), y.x.iter().copied())
    }

    /// The estimate from the simulation's positions `x` and the shadow's `y`, point by point.
    fn compare(&self, x: impl Iterator<Item = Vec3>, y: impl Iterator<Item = Vec3>) -> Option<ErrorEstimate> {
        let (mut sum, mut max) = (0.0f64, 0.0f32);
        for (p, s) in x.zip(y) {
            let d = (p - s).length();
            sum += d as f64 * d as f64;
            max = max.max(d);
        }
        let rms = (sum / self.points.len() as f64).sqrt() as f32;
        Some(ErrorEstimate {
            rms: rms * self.richardson,
            max: max * self.richardson,
        })
    }
}
