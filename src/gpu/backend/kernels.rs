//! The hair kernels of one scene variant (dry or wet): compiled from the plan's pass list and
//! encoded once per substep.

use super::super::buffers::groups;
use super::super::pipelines::{self as pl, SceneConsts};
use super::stamps::{close, PassStamps};
use super::{GpuBackend, MAX_IMPLICIT_POINTS};
use crate::error::{Error, Result};
use crate::params::Integrator;
use crate::physics::bdf2::Bdf2Clock;
use crate::plan::{pass_list, Pass};
use crate::timers::Stage;

/// The hair kernels of one scene variant (dry or wet).
#[derive(Debug)]
pub(super) struct HairKernels {
    /// hair_forces: implicit Euler's explicit forces (only with drag or water).
    pub(super) forces: Option<wgpu::ComputePipeline>,
    /// hair_substep (symplectic Euler) or implicit_solve (one invocation per strand).
    pub(super) solve: wgpu::ComputePipeline,
    /// Whether `solve` is implicit_solve.
    pub(super) implicit: bool,
    /// water_integrate (wet only).
    pub(super) water: Option<wgpu::ComputePipeline>,
    /// cohesion (scenes with liquid bridges only): parks each point's pull for the kernels
    /// after it.
    pub(super) cohesion: Option<wgpu::ComputePipeline>,
}

impl HairKernels {
    /// Compiles the hair module for `passes`. `water`: the water group's layout when wet;
    /// `strands`: the strand table's layout for implicit Euler; `bridges`: the bridge records'
    /// layout when the scene has liquid bridges.
    pub(super) fn new(
        d: &wgpu::Device,
        consts: SceneConsts,
        passes: &[Pass],
        hair: &wgpu::BindGroupLayout,
        water: Option<&wgpu::BindGroupLayout>,
        strands: Option<&wgpu::BindGroupLayout>,
        bridges: Option<&wgpu::BindGroupLayout>,
    ) -> HairKernels {
        let implicit = passes.contains(&Pass::ImplicitSolve);
        let module = pl::module(d, "hair", &pl::hair_source(consts, passes));
        let main: Vec<Option<&wgpu::BindGroupLayout>> = vec![Some(hair), water];
        let one = |layouts: &[Option<&wgpu::BindGroupLayout>], e: &str| {
            pl::pipelines_sparse(d, &module, layouts, &[e]).remove(0)
        };
        HairKernels {
            forces: (implicit && pl::has_forces(passes)).then(|| one(&main, "hair_forces")),
            solve: if implicit {
                one(&[Some(hair), None, strands], "implicit_solve")
            } else {
                one(&main, "hair_substep")
            },
            implicit,
            water: water.map(|_| one(&main, "water_integrate")),
            cohesion: bridges
                .filter(|_| passes.contains(&Pass::Cohesion))
                .map(|l| one(&[Some(hair), None, None, Some(l)], "cohesion")),
        }
    }

    /// Encodes one substep's hair kernels (not water_integrate); `bridges` is the bridge
    /// records' group when the scene has them; `stamps` closes the stages `cohesion` and
    /// `blocks` when stage timing is on.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn encode(
        &self,
        pass: &mut wgpu::ComputePass,
        hair: &wgpu::BindGroup,
        off: &[u32],
        water: Option<&wgpu::BindGroup>,
        strands: Option<&wgpu::BindGroup>,
        bridges: Option<&wgpu::BindGroup>,
        points: u32,
        n_strands: u32,
        stamps: &mut Option<PassStamps>,
    ) {
        let (px, py) = groups(points);
        pass.set_bind_group(0, hair, off);
        if let (Some(p), Some(bg)) = (&self.cohesion, bridges) {
            pass.set_pipeline(p);
            pass.set_bind_group(3, bg, &[]);
            pass.dispatch_workgroups(px, py, 1);
            close(stamps, pass, Stage::Cohesion);
        }
        if let Some(f) = &self.forces {
            pass.set_pipeline(f);
            if let Some(w) = water {
                pass.set_bind_group(1, w, &[]);
            }
            pass.dispatch_workgroups(px, py, 1);
        }
        pass.set_pipeline(&self.solve);
        if self.implicit {
            if let Some(s) = strands {
                pass.set_bind_group(2, s, &[]);
            }
            let (sx, sy) = groups(n_strands);
            pass.dispatch_workgroups(sx, sy, 1);
        } else {
            if let Some(w) = water {
                pass.set_bind_group(1, w, &[]);
            }
            pass.dispatch_workgroups(px, py, 1);
        }
        close(stamps, pass, Stage::Blocks);
    }
}

impl GpuBackend {
    /// Runs `integrator` from the next step on (the error budget's AUTO choice): compiles its
    /// hair kernels, dry and (once water exists) wet, and gives the implicit integrators their
    /// strand table. BDF2 starts again from a backward Euler step, as after a reset. The
    /// compile is a one-off cost of each switch (tens of milliseconds on a driver that does
    /// not cache pipelines). XPBD, and the implicit integrators on strands longer than
    /// [`MAX_IMPLICIT_POINTS`], are refused as at create.
    pub fn set_integrator(&mut self, integrator: Integrator) -> Result<()> {
        if integrator == self.integrator {
            return Ok(());
        }
        if integrator == Integrator::XPBD
            || (integrator.is_implicit() && self.consts.max_points as usize > MAX_IMPLICIT_POINTS)
        {
            return Err(Error::Unsupported(format!(
                "the GPU backend cannot switch this groom to {integrator:?}"
            )));
        }
        let bdf2 = integrator == Integrator::BDF2;
        if integrator.is_implicit() && (self.strands_bg.is_none() || (bdf2 && !self.strands_history)) {
            let (layout, bg) = super::strand_table(&self.dev, &self.strand_first, bdf2, self.points as u64 * 32);
            self.strands_layout = Some(layout);
            self.strands_bg = Some(bg);
            self.strands_history = bdf2;
        }
        self.consts.bdf2 = bdf2;
        let d = &self.dev.device;
        let cohesion = self.bridges.as_ref().map(|b| &b.cohesion_layout);
        let kernels = |wet: bool, water: Option<&wgpu::BindGroupLayout>| {
            HairKernels::new(
                d,
                self.consts,
                &pass_list(&self.params, integrator, self.bend, wet),
                &self.hair_layout,
                water,
                self.strands_layout.as_ref(),
                cohesion,
            )
        };
        let dry = kernels(false, None);
        let wet = self.water.as_ref().map(|w| kernels(true, Some(&w.hair_layout)));
        self.dry_hair = dry;
        if let (Some(w), Some(k)) = (&mut self.water, wet) {
            w.wet_hair = k;
        }
        self.integrator = integrator;
        self.bdf2 = Bdf2Clock::default();
        self.dev.check()
    }
}
