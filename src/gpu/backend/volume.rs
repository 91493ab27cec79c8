//! Hair-hair volume on the GPU (`physics/volume.rs`, `volume.wgsl`): the grid's sums (eight
//! words a sample: mass and momentum as 64-bit integers), the step's uniform, and pass volume
//! as two kernels, `volume_spread` (integer atomics: the same grid in any order) and
//! `volume_respond`, run once a step before the substeps, after the held water's masses.
//! Nothing here exists without hair-hair volume.

use super::super::buffers::{self as b, groups, VolumeStepGpu, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use crate::error::{Error, Result};
use crate::physics::volume::{VolumeGrid, VolumeLaw, MASS_QUANTUM};
use glam::Affine3A;

/// Words per sample: mass, momentum x, y, z, each a low and a high word.
const WORDS: u64 = 8;

/// The grid, its uniform and the two kernels.
#[derive(Debug)]
pub(super) struct VolumeGpu {
    grid: VolumeGrid,
    rest: f32,
    params: crate::params::Volume,
    pub(super) points: u32,
    sums: wgpu::Buffer,
    uniform: wgpu::Buffer,
    spread: wgpu::ComputePipeline,
    respond: wgpu::ComputePipeline,
    /// Over state `i`.
    bg: [wgpu::BindGroup; 2],
}

impl VolumeGpu {
    /// The grid's buffers over `points` hair points; refused where the sums exceed what the
    /// device binds as one storage buffer.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        d: &wgpu::Device,
        c: SceneConsts,
        groom: &crate::groom::Groom,
        p: &crate::params::Volume,
        hair_points: &wgpu::Buffer,
        state: &[wgpu::Buffer; 2],
        max_storage: u64,
    ) -> Result<VolumeGpu> {
        let grid = VolumeGrid::for_groom(groom, p.cell)?;
        let rest = crate::physics::volume::rest_density_of(p, &grid, groom);
        let bytes = grid.cells() as u64 * WORDS * 4;
        if bytes > max_storage {
            return Err(Error::Unsupported(format!(
                "the volume grid's {bytes} bytes exceed the device's storage binding ({max_storage} bytes); raise volume.cell"
            )));
        }
        let sums = b::buffer(d, "volume_grid", bytes, STORAGE);
        let uniform = b::buffer(
            d,
            "volume_step",
            std::mem::size_of::<VolumeStepGpu>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let layout = pl::layout(
            d,
            "volume",
            &[Slot::Uniform, Slot::Read, Slot::ReadWrite, Slot::ReadWrite],
        );
        let mk = |i: usize| pl::bind(d, "volume", &layout, &[&uniform, hair_points, &state[i], &sums], None);
        let spread_mod = pl::module(d, "volume spread", &pl::volume_spread_source(c));
        let respond_mod = pl::module(d, "volume respond", &pl::volume_respond_source(c));
        let spread = pl::pipelines(d, &spread_mod, &[&layout], &["volume_spread"]).remove(0);
        let respond = pl::pipelines(d, &respond_mod, &[&layout], &["volume_respond"]).remove(0);
        let bg = [mk(0), mk(1)];
        Ok(VolumeGpu {
            grid,
            rest,
            params: *p,
            points: groom.point_count() as u32,
            sums,
            uniform,
            spread,
            respond,
            bg,
        })
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        (self.sums.size() + self.uniform.size()) as usize
    }

    /// Writes the step's uniform (a step of `dt` from under `head`) and clears the grid; both
    /// land before the step's pass.
    pub(super) fn prepare(&self, q: &wgpu::Queue, enc: &mut wgpu::CommandEncoder, head: &Affine3A, dt: f32) {
        let to_head = head.inverse();
        let law = VolumeLaw::new(&self.params, self.rest, dt, glam::Mat3::from(head.matrix3));
        let row = |m: &glam::Mat3A, i: usize, w: f32| {
            let r = m.row(i);
            [r.x, r.y, r.z, w]
        };
        let t = to_head.translation;
        let w = glam::Mat3A::from(law.to_world);
        let g = &self.grid;
        let u = VolumeStepGpu {
            hx: row(&to_head.matrix3, 0, t.x),
            hy: row(&to_head.matrix3, 1, t.y),
            hz: row(&to_head.matrix3, 2, t.z),
            wx: row(&w, 0, 0.0),
            wy: row(&w, 1, 0.0),
            wz: row(&w, 2, 0.0),
            origin: g.origin.extend(g.cell).to_array(),
            dims: [g.dims[0], g.dims[1], g.dims[2], self.points],
            law: [
                law.blend,
                law.push,
                self.rest,
                (MASS_QUANTUM / (g.cell as f64).powi(3)) as f32,
            ],
        };
        q.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&u));
        enc.clear_buffer(&self.sums, 0, None);
    }

    /// Pass volume over state `cur`.
    pub(super) fn encode(&self, pass: &mut wgpu::ComputePass, cur: usize) {
        let (gx, gy) = groups(self.points);
        pass.set_bind_group(0, &self.bg[cur], &[]);
        pass.set_pipeline(&self.spread);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_pipeline(&self.respond);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}
