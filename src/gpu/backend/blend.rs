//! The output blend of fixed-step updates (`sim/fixed.rs`): a copy of the state kept before
//! an advance's last step, and the vertex pass that writes it moved toward the current state
//! (`output.wgsl` `write_vertices_blended`). Nothing here exists until a simulation first
//! keeps a state.

use super::super::buffers::{self as b, BlendGpu, STORAGE};
use super::super::pipelines::{self as pl, Slot};
use super::GpuBackend;
use crate::error::Result;

/// The kept state, the blend's uniform, and the blended vertex pass's pipeline and bind groups
/// (one per current state buffer).
#[derive(Debug)]
pub(super) struct OutputBlend {
    from: wgpu::Buffer,
    uniform: wgpu::Buffer,
    pub(super) pipe: wgpu::ComputePipeline,
    pub(super) bg: [wgpu::BindGroup; 2],
    /// Whether the vertex pass blends now.
    pub(super) on: bool,
}

impl OutputBlend {
    /// The kept state.
    pub(super) fn from(&self) -> &wgpu::Buffer {
        &self.from
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        (self.from.size() + self.uniform.size()) as usize
    }
}

impl GpuBackend {
    /// Copies the current state to where the output blend starts (on the queue, before the
    /// next step), creating the blend's buffers and pipeline on the first call.
    pub fn keep_previous(&mut self) -> Result<()> {
        if self.blend.is_none() {
            self.blend = Some(self.create_blend());
            self.rebind_followers();
        }
        let blend = self.blend.as_ref().expect("created above");
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(
            &self.state[self.cur],
            0,
            &blend.from,
            0,
            Some(self.state[self.cur].size()),
        );
        self.submit(enc);
        self.dev.check()
    }

    /// Blends the vertex output by `a` from now on (`None`: the state itself). Nothing to
    /// blend from until [`GpuBackend::keep_previous`]. The vertices are written again when
    /// next asked for (a read, or the host-shared buffer's `shared_frame`), step or not.
    pub fn blend_output(&mut self, a: Option<f32>) {
        let Some(blend) = &mut self.blend else {
            return;
        };
        blend.on = a.is_some();
        if let Some(a) = a {
            let rec = BlendGpu {
                a,
                pad0: 0,
                pad1: 0,
                pad2: 0,
            };
            self.dev.queue.write_buffer(&blend.uniform, 0, bytemuck::bytes_of(&rec));
        }
        self.followers_kept(a);
        self.vertices_current = false;
    }

    fn create_blend(&self) -> OutputBlend {
        let d = &self.dev.device;
        let from = b::buffer(d, "output_from", self.state[0].size(), STORAGE);
        let uniform = b::buffer(
            d,
            "output_blend",
            std::mem::size_of::<BlendGpu>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let layout = pl::layout(
            d,
            "output blended",
            &[
                Slot::Uniform,
                Slot::Read,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
                Slot::Read,
                Slot::Uniform,
            ],
        );
        let mk = |i: usize| {
            pl::bind(
                d,
                "output blended",
                &layout,
                &[
                    &self.params_buf,
                    &self.points_buf,
                    &self.state[i],
                    &self.status,
                    &self.vertices,
                    &from,
                    &uniform,
                ],
                None,
            )
        };
        let bg = [mk(0), mk(1)];
        let module = pl::module(d, "output", &pl::output_source(self.consts));
        let pipe = pl::pipelines(d, &module, &[&layout], &["write_vertices_blended"]).remove(0);
        OutputBlend {
            from,
            uniform,
            pipe,
            bg,
            on: false,
        }
    }
}
