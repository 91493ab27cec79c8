//! Time per stage of a step, behind a switch, for both backends: the CPU reads the wall clock
//! before and after each stage; the GPU books the intervals between timestamps it writes
//! after each stage (`gpu::backend::stamps`). Off (the default) a stage costs one branch. The
//! benches print the totals beside each row, so a frame's time is seen pass by pass, under
//! the same names on both backends.

use crate::engine::PassTime;
use crate::plan::Pass;
use std::time::{Duration, Instant};

/// A step's stages, in the order a step runs them. The CPU's block kernel runs the pass list's
/// per-point passes (drag, springs, adhesion, integrate, collide) together, block by block, so
/// they are one stage, `blocks`; on the GPU `blocks` is the same passes' kernels
/// (`hair_substep`, or `hair_forces` and `implicit_solve`). The rest are the pass list's own
/// passes, named as there (`wet_params` is the held water's masses and limpness, `vertices`
/// the host's copy). The CPU runs the held water's passes after the substeps block by block
/// too (`cpu/settle.rs`): its `flow` stage is that sweep (each block's flow, and for the
/// blocks that shed no drop their drying, saturation and the next step's `wet_params`), its
/// `drip` the serial drip, its `dry` the blocks that shed drops, finished after it; its
/// `wet_params` is left with work only when the host changed the water between steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Held water's masses and limpness (and the velocities flow reads).
    WetParams,
    /// Pass `hair_grid`: the liquid bridges' search.
    HairGrid,
    /// Pass `volume`: hair-hair volume's grid and response.
    Volume,
    /// Pass `water_grid`.
    WaterGrid,
    /// Pass `cohesion`: the bridges' pulls. On the CPU this stage is the wet points'
    /// positions packed once a step; the block kernel pulls each substep (in `blocks`).
    Cohesion,
    /// The block kernel (drag, springs, adhesion, cohesion's pulls on the CPU, integrate,
    /// collide).
    Blocks,
    /// Pass `absorb`.
    Absorb,
    /// Pass `water_integrate`.
    WaterIntegrate,
    /// Pass `flow`.
    Flow,
    /// Pass `drip`.
    Drip,
    /// Pass `dry`, and the saturation the vertices show (on the GPU its own kernel, booked
    /// here).
    Dry,
    /// Pass `water_cull`.
    WaterCull,
    /// The host's copy of the vertices.
    Vertices,
}

/// Every stage, in step order.
const STAGES: [Stage; 13] = [
    Stage::WetParams,
    Stage::HairGrid,
    Stage::Volume,
    Stage::WaterGrid,
    Stage::Cohesion,
    Stage::Blocks,
    Stage::Absorb,
    Stage::WaterIntegrate,
    Stage::Flow,
    Stage::Drip,
    Stage::Dry,
    Stage::WaterCull,
    Stage::Vertices,
];

impl Stage {
    /// The stage's name (a pass's name where the stage is one pass).
    pub fn name(self) -> &'static str {
        match self {
            Stage::WetParams => "wet_params",
            Stage::HairGrid => Pass::HairGrid.name(),
            Stage::Volume => Pass::Volume.name(),
            Stage::WaterGrid => Pass::WaterGrid.name(),
            Stage::Cohesion => Pass::Cohesion.name(),
            Stage::Blocks => "blocks",
            Stage::Absorb => Pass::Absorb.name(),
            Stage::WaterIntegrate => Pass::WaterIntegrate.name(),
            Stage::Flow => Pass::Flow.name(),
            Stage::Drip => Pass::Drip.name(),
            Stage::Dry => Pass::Dry.name(),
            Stage::WaterCull => Pass::WaterCull.name(),
            Stage::Vertices => "vertices",
        }
    }
}

/// Time and runs per stage since the clock was switched on.
#[derive(Debug, Default)]
pub struct StageClock {
    on: bool,
    total: [Duration; STAGES.len()],
    runs: [u64; STAGES.len()],
}

impl StageClock {
    /// Switches timing on (totals start from zero) or off.
    pub fn set(&mut self, on: bool) {
        *self = StageClock {
            on,
            ..Default::default()
        };
    }

    /// The time a stage starts, when timing is on.
    #[inline]
    pub fn start(&self) -> Option<Instant> {
        self.on.then(Instant::now)
    }

    /// Books the time since `start` (from [`StageClock::start`]) to `stage`.
    #[inline]
    pub fn stop(&mut self, stage: Stage, start: Option<Instant>) {
        if let Some(t) = start {
            self.add(stage, t.elapsed());
        }
    }

    /// Books one run of `stage` that took `took` (measured elsewhere: GPU timestamps).
    pub fn add(&mut self, stage: Stage, took: Duration) {
        self.total[stage as usize] += took;
        self.runs[stage as usize] += 1;
    }

    /// Whether timing is on.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// The stages that ran, in step order, with their totals.
    pub fn times(&self) -> Vec<PassTime> {
        STAGES
            .iter()
            .filter(|&&s| self.runs[s as usize] > 0)
            .map(|&s| PassTime {
                name: s.name(),
                ms: self.total[s as usize].as_secs_f64() * 1e3,
                runs: self.runs[s as usize],
            })
            .collect()
    }
}
