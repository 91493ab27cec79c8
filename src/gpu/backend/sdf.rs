//! SDF colliders on the GPU (`physics/sdf.rs`, `sdf.wgsl`): every grid's samples in one
//! storage buffer, each substep's placements in a uniform at the substep's offset, and two
//! passes: `hair_sdf` after each substep's hair kernel and `water_sdf` after each
//! `water_integrate`, in the CPU's order (analytic colliders, then the fields). Nothing here
//! exists in a scene without SDFs.

use super::super::buffers::{self as b, groups, SdfGpu, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use crate::error::{Error, Result};
use crate::physics::head::head_between;
use crate::physics::sdf::{PlacedSdf, Sdf};
use glam::Affine3A;
use std::sync::Arc;

/// The fields' buffers, passes and transforms.
#[derive(Debug)]
pub(super) struct SdfColliders {
    grids: Vec<Arc<Sdf>>,
    /// Where each grid's samples start in `values`.
    starts: Vec<u32>,
    values: wgpu::Buffer,
    /// Each substep's placements, `stride` apart.
    sub: wgpu::Buffer,
    stride: u64,
    bytes: Vec<u8>,
    hair_pipe: wgpu::ComputePipeline,
    /// Over the state the hair kernel writes from state `i`: state `1 - i`.
    hair_bg: [wgpu::BindGroup; 2],
    water_pipe: wgpu::ComputePipeline,
    water_layout: wgpu::BindGroupLayout,
    /// Over the particles `water_integrate` writes from `i` (made once particles exist).
    pub(super) water_bg: Option<[wgpu::BindGroup; 2]>,
    /// The transforms at the start and the end of the next step.
    from: Vec<Affine3A>,
    to: Vec<Affine3A>,
}

/// The inputs the passes bind that the backend owns.
pub(super) struct SdfInputs<'a> {
    pub params: &'a wgpu::Buffer,
    pub points: &'a wgpu::Buffer,
    pub state: &'a [wgpu::Buffer; 2],
    pub most_sub: usize,
    pub align: u64,
    pub max_storage: u64,
}

impl SdfColliders {
    /// Uploads `grids` and builds the passes; refused where the samples exceed what the device
    /// binds as one storage buffer.
    pub(super) fn new(
        d: &wgpu::Device,
        q: &wgpu::Queue,
        c: SceneConsts,
        grids: &[Arc<Sdf>],
        at: SdfInputs,
    ) -> Result<Self> {
        let mut starts = Vec::with_capacity(grids.len());
        let mut all: Vec<f32> = Vec::new();
        for g in grids {
            starts.push(all.len() as u32);
            all.extend_from_slice(&g.values);
        }
        let bytes = (all.len() * 4) as u64;
        if bytes > at.max_storage || all.len() > u32::MAX as usize {
            return Err(Error::Unsupported(format!(
                "the SDF colliders' {bytes} bytes of samples exceed the device's storage binding ({} bytes)",
                at.max_storage
            )));
        }
        let values = b::buffer(d, "sdf_values", bytes, STORAGE);
        q.write_buffer(&values, 0, bytemuck::cast_slice(&all));
        let rec = std::mem::size_of::<SdfGpu>() as u64;
        let size = rec * grids.len() as u64;
        let stride = size.next_multiple_of(at.align);
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let sub = b::buffer(d, "sdf_substeps", stride * at.most_sub as u64, uniform);
        let ns = grids.len();
        let hair_layout = pl::layout(
            d,
            "sdf hair",
            &[
                Slot::Uniform,
                Slot::UniformDynamic,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
            ],
        );
        let mk = |i: usize| {
            pl::bind(
                d,
                "sdf hair",
                &hair_layout,
                &[at.params, &sub, &values, at.points, &at.state[1 - i]],
                Some((1, size)),
            )
        };
        let hair_bg = [mk(0), mk(1)];
        let hair_mod = pl::module(d, "sdf hair", &pl::sdf_hair_source(c, ns));
        let hair_pipe = pl::pipelines(d, &hair_mod, &[&hair_layout], &["hair_sdf"]).remove(0);
        let water_layout = pl::layout(
            d,
            "sdf water",
            &[
                Slot::Uniform,
                Slot::UniformDynamic,
                Slot::Read,
                Slot::ReadWrite,
                Slot::Read,
            ],
        );
        let water_mod = pl::module(d, "sdf water", &pl::sdf_water_source(c, ns));
        let water_pipe = pl::pipelines(d, &water_mod, &[&water_layout], &["water_sdf"]).remove(0);
        Ok(SdfColliders {
            grids: grids.to_vec(),
            starts,
            values,
            sub,
            stride,
            bytes: Vec::new(),
            hair_pipe,
            hair_bg,
            water_pipe,
            water_layout,
            water_bg: None,
            from: grids.iter().map(|g| g.transform).collect(),
            to: grids.iter().map(|g| g.transform).collect(),
        })
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        (self.values.size() + self.sub.size()) as usize
    }

    /// Moves the fields from `from` to `to` over the next step.
    pub(super) fn place(&mut self, from: &[Affine3A], to: &[Affine3A]) {
        self.from.clear();
        self.from.extend_from_slice(from);
        self.to.clear();
        self.to.extend_from_slice(to);
    }

    /// Uploads each of `n_sub` substeps' placements (the transforms interpolated as the CPU
    /// interpolates them, moving over substeps of `1 / inv_h` s).
    pub(super) fn write_substeps(&mut self, q: &wgpu::Queue, n_sub: usize, inv_h: f32) {
        let rec = std::mem::size_of::<SdfGpu>();
        self.bytes.clear();
        self.bytes.resize(self.stride as usize * n_sub, 0);
        for s in 0..n_sub {
            for (k, g) in self.grids.iter().enumerate() {
                let path = |a: usize| head_between(&self.from[k], &self.to[k], a as f32 / n_sub as f32);
                let at = PlacedSdf::moving(g, &path(s), &path(s + 1), inv_h);
                let r = record(g, &at, self.starts[k]);
                let at = s * self.stride as usize + k * rec;
                self.bytes[at..at + rec].copy_from_slice(bytemuck::bytes_of(&r));
            }
        }
        q.write_buffer(&self.sub, 0, &self.bytes);
    }

    /// Pass collide's SDF part for the hair of substep `s`, over the state the hair kernel
    /// wrote from state `cur`.
    pub(super) fn encode_hair(&self, pass: &mut wgpu::ComputePass, cur: usize, s: usize, points: u32) {
        pass.set_pipeline(&self.hair_pipe);
        pass.set_bind_group(0, &self.hair_bg[cur], &[(s as u64 * self.stride) as u32]);
        let (gx, gy) = groups(points);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// The particles' bind groups, over `particles` as `water_integrate` writes them and the
    /// water grid's count.
    pub(super) fn water_groups(
        &self,
        d: &wgpu::Device,
        params: &wgpu::Buffer,
        particles: &[wgpu::Buffer; 2],
        grid: &wgpu::Buffer,
    ) -> [wgpu::BindGroup; 2] {
        let size = (std::mem::size_of::<SdfGpu>() * self.grids.len()) as u64;
        let mk = |i: usize| {
            pl::bind(
                d,
                "sdf water",
                &self.water_layout,
                &[params, &self.sub, &self.values, &particles[1 - i], grid],
                Some((1, size)),
            )
        };
        [mk(0), mk(1)]
    }

    /// The particles' SDF pass of substep `s` (after `water_integrate` from particles `cur`).
    pub(super) fn encode_water(&self, pass: &mut wgpu::ComputePass, cur: usize, s: usize, bound: u32) {
        let Some(bg) = &self.water_bg else {
            return;
        };
        pass.set_pipeline(&self.water_pipe);
        pass.set_bind_group(0, &bg[cur], &[(s as u64 * self.stride) as u32]);
        let (gx, gy) = groups(bound);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}

/// Grid `g` placed at `at`, its samples from `start`, as the shader reads it.
fn record(g: &Sdf, at: &PlacedSdf, start: u32) -> SdfGpu {
    let row = |m: &glam::Mat3A, i: usize| m.row(i).to_array();
    let gm = &at.to_grid.matrix3;
    let t = at.to_grid.translation;
    let wm = &at.to_world.matrix3;
    let r4 = |r: [f32; 3], w: f32| [r[0], r[1], r[2], w];
    SdfGpu {
        gx: r4(row(gm, 0), t.x),
        gy: r4(row(gm, 1), t.y),
        gz: r4(row(gm, 2), t.z),
        wx: r4(row(wm, 0), 0.0),
        wy: r4(row(wm, 1), 0.0),
        wz: r4(row(wm, 2), 0.0),
        lo: at.lo.extend(at.scale).to_array(),
        hi: at.hi.extend(g.cell).to_array(),
        origin: g.origin.extend(0.0).to_array(),
        dims: [g.dims[0], g.dims[1], g.dims[2], start],
        vx: r4(row(&at.velocity.matrix3, 0), at.velocity.translation.x),
        vy: r4(row(&at.velocity.matrix3, 1), at.velocity.translation.y),
        vz: r4(row(&at.velocity.matrix3, 2), at.velocity.translation.z),
    }
}
