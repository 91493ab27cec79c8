//! The hair kernels of one scene variant (dry or wet): compiled from the plan's pass list and
//! encoded once per substep.

use super::super::buffers::groups;
use super::super::pipelines::{self as pl, SceneConsts};
use super::stamps::{close, PassStamps};
use crate::plan::Pass;
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
