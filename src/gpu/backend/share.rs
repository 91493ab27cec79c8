//! Sharing with the host's Vulkan: the vertex buffer and its semaphore values, the water's
//! buffers for an indirect draw (made at the host's first ask), and the status ring that
//! reports a failed step to a host that never reads through us.

#[cfg(feature = "vulkan")]
use super::super::buffers::{self as b, STORAGE};
#[cfg(feature = "vulkan")]
use super::super::pipelines::{self as pl, Slot};
use super::readback::{decode_status, Staging, STATUS_BYTES};
use super::GpuBackend;
#[cfg(feature = "vulkan")]
use crate::error::{Error, Result};
use std::sync::atomic::Ordering;

/// Host-shared devices whose host draws the particles (made at its first ask): their
/// positions and the indirect draw's arguments, written with the vertices in the submission
/// that waits for the host's release.
#[derive(Debug)]
pub(super) struct WaterShare {
    pub(super) vertices: wgpu::Buffer,
    pub(super) draw: wgpu::Buffer,
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) pipe: wgpu::ComputePipeline,
    /// By `WaterGpu::cur`, once the particles exist.
    pub(super) bg: Option<[wgpu::BindGroup; 2]>,
}

impl GpuBackend {
    /// Hands the host the vertex buffer of the last step, with the semaphore values that
    /// order its reads against our next write (see [`crate::gpu::vulkan::SharedSync`]).
    #[cfg(feature = "vulkan")]
    pub fn shared_frame(&mut self) -> Result<crate::gpu::vulkan::SharedFrame> {
        use crate::gpu::vulkan::{raw_buffer, raw_semaphore, SharedFrame};
        self.dev.check()?;
        if self.dev.shared.is_none() {
            return Err(Error::Unsupported(
                "the vertex VkBuffer is shared only by simulations created on the host's VkDevice".into(),
            ));
        }
        if !self.vertices_current {
            let mut enc = self.dev.device.create_command_encoder(&Default::default());
            self.vertices_current = false;
            self.encode_vertices(&mut enc);
            self.submit(enc);
        }
        // A failed step seen by the status ring is reported here, not handed out.
        self.poll_status_ring();
        self.status_error(&self.last)?;
        let buffer =
            raw_buffer(&self.vertices).ok_or_else(|| Error::Device("the vertex buffer has no Vulkan handle".into()))?;
        let Some(sync) = self.dev.shared.as_ref() else {
            return Err(Error::Unsupported("no shared device".into()));
        };
        let (ready, release) = sync.acquire();
        self.dev.check()?;
        Ok(SharedFrame {
            buffer,
            size: self.vertices.size(),
            ready_semaphore: raw_semaphore(sync.ready),
            ready_value: ready,
            release_semaphore: raw_semaphore(sync.release),
            release_value: release,
        })
    }

    /// Hands the host the particles' positions and indirect-draw arguments as Vulkan buffers,
    /// written with each frame's vertices (the frame's semaphores cover them). The first call
    /// makes them (capacity x 16 bytes + 16) and writes the current particles at once.
    #[cfg(feature = "vulkan")]
    pub fn shared_water(&mut self) -> Result<crate::gpu::vulkan::SharedWater> {
        use crate::gpu::vulkan::{raw_buffer, SharedWater};
        self.dev.check()?;
        if self.dev.shared.is_none() {
            return Err(Error::Unsupported(
                "the water VkBuffers are shared only by simulations created on the host's VkDevice".into(),
            ));
        }
        if self.water_share.is_none() {
            let d = &self.dev.device;
            let cap = self.params.water.capacity as u64;
            let layout = pl::layout(
                d,
                "water output",
                &[Slot::Read, Slot::Read, Slot::Read, Slot::ReadWrite, Slot::ReadWrite],
            );
            let module = pl::module(d, "water output", &pl::water_output_source(self.consts));
            let pipe = pl::pipelines(d, &module, &[&layout], &["write_water_vertices"]).remove(0);
            self.water_share = Some(WaterShare {
                vertices: b::buffer(d, "water_vertices", cap * 16, STORAGE | wgpu::BufferUsages::VERTEX),
                draw: b::buffer(d, "water_draw", 16, STORAGE | wgpu::BufferUsages::INDIRECT),
                layout,
                pipe,
                bg: None,
            });
            // The frame already handed out was written without them: write them now and wait,
            // so that the host's next read of this frame finds them (nobody reads them yet).
            // wgpu zero-fills a buffer lazily, at its first use by wgpu, and the host's own
            // commands are not that: clear the draw arguments here, so that a host drawing
            // before any water exists draws nothing rather than what the memory held.
            let mut enc = self.dev.device.create_command_encoder(&Default::default());
            if let Some(ws) = &self.water_share {
                enc.clear_buffer(&ws.draw, 0, None);
            }
            self.encode_water_vertices(&mut enc);
            self.submit(enc);
            self.dev.wait()?;
        }
        let ws = self.water_share.as_ref().expect("made above");
        let handle = |buf| raw_buffer(buf).ok_or_else(|| Error::Device("a water buffer has no Vulkan handle".into()));
        Ok(SharedWater {
            buffer: handle(&ws.vertices)?,
            capacity: self.params.water.capacity,
            draw_buffer: handle(&ws.draw)?,
        })
    }

    /// Picks a free status-ring slot and records the copy of the status block into it; None
    /// when both still wait for the GPU (this step's status is then skipped, never waited for).
    /// Slots whose readback has landed are decoded first: a failed step shows at the next call.
    pub(super) fn status_slot(&mut self, enc: &mut wgpu::CommandEncoder) -> Option<usize> {
        if self.status_ring.is_empty() {
            for _ in 0..2 {
                self.status_ring
                    .push(Staging::new(&self.dev.device, "status readback", STATUS_BYTES));
            }
        }
        self.poll_status_ring();
        let k = self.status_ring.iter().position(|s| s.frame.is_none())?;
        let dst = &self.status_ring[k].buf;
        enc.copy_buffer_to_buffer(&self.status, 0, dst, 0, Some(16));
        if let Some(w) = &self.water {
            enc.copy_buffer_to_buffer(&w.state, 0, dst, 16, Some(16));
        }
        Some(k)
    }

    /// Decodes the status-ring slots whose readback has landed (without waiting) into
    /// `last`, the newest step first, and frees them.
    pub(super) fn poll_status_ring(&mut self) {
        let _ = self.dev.device.poll(wgpu::PollType::Poll);
        let mut landed: Vec<usize> = (0..self.status_ring.len())
            .filter(|&k| self.status_ring[k].frame.is_some() && self.status_ring[k].ready.load(Ordering::Acquire))
            .collect();
        landed.sort_by_key(|&k| self.status_ring[k].frame);
        for k in landed {
            let s = &mut self.status_ring[k];
            if let Ok(view) = s.buf.get_mapped_range(..) {
                let (st, _) = decode_status(bytemuck::cast_slice(&view), self.water.is_some());
                // A failure, once seen, stays until reset; otherwise the newest status wins.
                if self.last.failed_point.is_none() && !self.last.water_failed {
                    self.last = st;
                }
            }
            s.buf.unmap();
            s.frame = None;
            s.ready.store(false, Ordering::Release);
        }
    }
}
