//! Reading back from the device: the staging ring for vertices (latest or one frame behind),
//! the status block that rides along, and blocking copies for diagnostics.

use super::super::buffers::{self as b, status as st, water_state as ws, StateGpu};
use super::{GpuBackend, Status};
use crate::error::{Error, Result};
use crate::params::Readback;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Bytes of the status block at the start of every readback: hair status then water state.
pub(super) const STATUS_BYTES: u64 = 32;

/// One staging buffer of the readback ring.
#[derive(Debug)]
pub(super) struct Staging {
    pub(super) buf: wgpu::Buffer,
    /// The step whose vertices it holds (mapped or being mapped), if any.
    pub(super) frame: Option<u64>,
    pub(super) ready: Arc<AtomicBool>,
}

impl Staging {
    /// An unmapped staging buffer of `size` bytes that holds no frame yet.
    pub(super) fn new(dev: &wgpu::Device, label: &str, size: u64) -> Staging {
        Staging {
            buf: b::buffer(
                dev,
                label,
                size,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            frame: None,
            ready: Arc::default(),
        }
    }

    /// Maps the buffer for reading once the work submitted so far is done, as holding `frame`.
    pub(super) fn map(&mut self, frame: u64) {
        self.frame = Some(frame);
        let ready = self.ready.clone();
        self.buf.map_async(wgpu::MapMode::Read, .., move |r| {
            // A failed map leaves `ready` false; the reader then reports the device error.
            if r.is_ok() {
                ready.store(true, Ordering::Release);
            }
        });
    }

    /// Unmaps the buffer if it holds a frame (waiting for its map to finish first), so that a
    /// copy may write it again.
    pub(super) fn settle(&mut self, dev: &wgpu::Device) {
        if self.frame.take().is_some() {
            while !self.ready.load(Ordering::Acquire) {
                if dev.poll(wgpu::PollType::wait_indefinitely()).is_err() {
                    break;
                }
            }
            self.buf.unmap();
            self.ready.store(false, Ordering::Release);
        }
    }
}

impl GpuBackend {
    pub(super) fn ensure_staging(&mut self) {
        if !self.staging.is_empty() {
            return;
        }
        let n = if self.params.readback == Readback::PREVIOUS_FRAME {
            2
        } else {
            1
        };
        let size = STATUS_BYTES + self.vertices.size();
        for _ in 0..n {
            self.staging.push(Staging::new(&self.dev.device, "readback", size));
        }
    }

    /// Unmaps staging slot `k` if it still holds an older frame.
    pub(super) fn settle(&mut self, k: usize) {
        self.staging[k].settle(&self.dev.device);
    }

    pub(super) fn encode_copy(&self, enc: &mut wgpu::CommandEncoder, k: usize) {
        let dst = &self.staging[k].buf;
        enc.copy_buffer_to_buffer(&self.status, 0, dst, 0, Some(16));
        if let Some(w) = &self.water {
            enc.copy_buffer_to_buffer(&w.state, 0, dst, 16, Some(16));
        }
        enc.copy_buffer_to_buffer(&self.vertices, 0, dst, STATUS_BYTES, Some(self.vertices.size()));
    }

    pub(super) fn map(&mut self, (k, frame): (usize, u64)) {
        self.staging[k].map(frame);
    }

    /// Waits until slot `k` is mapped; then decodes its status.
    pub(super) fn wait_mapped(&mut self, k: usize) -> Result<Status> {
        while !self.staging[k].ready.load(Ordering::Acquire) {
            self.dev.wait()?;
            if !self.staging[k].ready.load(Ordering::Acquire) {
                self.dev.check()?;
                return Err(Error::Device("mapping the readback buffer failed".into()));
            }
        }
        let view = self.staging[k]
            .buf
            .get_mapped_range(..STATUS_BYTES)
            .map_err(|e| Error::Device(format!("reading back: {e}")))?;
        let (st, removed) = decode_status(bytemuck::cast_slice(&view), self.water.is_some());
        drop(view);
        if let Some(wt) = &mut self.water {
            wt.bound = st.particles;
            wt.removed = removed;
        }
        self.last = st;
        Ok(st)
    }

    pub(super) fn status_error(&self, st: &Status) -> Result<()> {
        if let Some(p) = st.failed_point {
            let strand = self.strand_first.partition_point(|&f| f <= p).saturating_sub(1) as u32;
            return Err(Error::Unstable {
                strand: Some(strand),
                detail: "a GPU step produced a non-finite position or velocity".into(),
            });
        }
        if st.water_failed {
            return Err(Error::Unstable {
                strand: None,
                detail: "a water particle became non-finite".into(),
            });
        }
        Ok(())
    }

    /// Copies the vertices into `dst` (`points * stride` floats). `Readback::LATEST` waits for
    /// the current step; `PreviousFrame` returns the step before it without waiting (the first
    /// read waits). Returns the step number the vertices belong to. Writes nothing on error.
    pub fn read_vertices(&mut self, dst: &mut [f32]) -> Result<u64> {
        self.dev.check()?;
        self.ensure_staging();
        let prev = self.frame.saturating_sub(1);
        let slot = match self.params.readback {
            Readback::PREVIOUS_FRAME => {
                let find = |f: u64| self.staging.iter().position(|s| s.frame == Some(f));
                find(prev).filter(|_| self.frame > 0).or_else(|| find(self.frame))
            }
            Readback::LATEST => None,
        };
        let k = match slot {
            Some(k) => k,
            None => {
                let k = (self.frame % self.staging.len() as u64) as usize;
                self.settle(k);
                let mut enc = self.dev.device.create_command_encoder(&Default::default());
                self.encode_vertices(&mut enc);
                self.encode_copy(&mut enc, k);
                self.submit(enc);
                self.map((k, self.frame));
                k
            }
        };
        let st = self.wait_mapped(k)?;
        self.status_error(&st)?;
        let frame = self.staging[k].frame.unwrap_or(self.frame);
        {
            let view = self.staging[k]
                .buf
                .get_mapped_range(STATUS_BYTES..STATUS_BYTES + dst.len() as u64 * 4)
                .map_err(|e| Error::Device(format!("reading back: {e}")))?;
            dst.copy_from_slice(bytemuck::cast_slice(&view));
        }
        // The slot stays mapped with its frame: a second read of the same frame finds it, and
        // `settle` unmaps it before it is written again.
        Ok(frame)
    }

    /// Reads the status of the last submitted step (waits for it) and remembers it.
    pub fn read_status(&mut self) -> Result<Status> {
        let (st, removed) = self.peek_status()?;
        if let Some(wt) = &mut self.water {
            wt.bound = st.particles;
            wt.removed = removed;
        }
        self.last = st;
        Ok(st)
    }

    /// Reads the status of the last submitted step (waits for it) and the particles removed.
    pub fn peek_status(&self) -> Result<(Status, u64)> {
        let bytes = self.read_buffers(&[(&self.status, 16)], self.water.as_ref().map(|w| &w.state))?;
        Ok(decode_status(bytemuck::cast_slice(&bytes[..32]), self.water.is_some()))
    }

    /// The error a status stands for (a non-finite point or particle), if any.
    pub fn check_status(&self, st: &Status) -> Result<()> {
        self.status_error(st)
    }

    /// The last status read.
    pub fn last_status(&self) -> Status {
        self.last
    }

    /// Particles removed since create or reset (as of the last status read).
    pub fn removed(&self) -> u64 {
        self.water.as_ref().map_or(0, |w| w.removed)
    }

    /// Blocking copy of whole buffers (`(buffer, bytes)`) plus an optional 16-byte tail.
    pub(super) fn read_buffers(&self, parts: &[(&wgpu::Buffer, u64)], tail: Option<&wgpu::Buffer>) -> Result<Vec<u8>> {
        let ranges: Vec<_> = parts.iter().map(|&(buf, n)| (buf, 0, n)).collect();
        self.read_ranges(&ranges, tail)
    }

    /// [`GpuBackend::read_buffers`] of byte ranges `(buffer, offset, length)`, each offset and
    /// length a multiple of 4 (a word of a large buffer is read without the words before it).
    pub(super) fn read_ranges(
        &self,
        parts: &[(&wgpu::Buffer, u64, u64)],
        tail: Option<&wgpu::Buffer>,
    ) -> Result<Vec<u8>> {
        self.dev.check()?;
        let total: u64 = parts.iter().map(|p| p.2).sum::<u64>() + 16;
        let tmp = b::buffer(
            &self.dev.device,
            "read",
            total,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for &(buf, from, n) in parts {
            if n > 0 {
                enc.copy_buffer_to_buffer(buf, from, &tmp, at, Some(n));
            }
            at += n;
        }
        if let Some(t) = tail {
            enc.copy_buffer_to_buffer(t, 0, &tmp, at, Some(16));
        }
        self.dev.submit(enc.finish(), false);
        let ok = Arc::new(AtomicBool::new(false));
        let flag = ok.clone();
        tmp.map_async(wgpu::MapMode::Read, .., move |r| {
            flag.store(r.is_ok(), Ordering::Release)
        });
        self.dev.wait()?;
        if !ok.load(Ordering::Acquire) {
            return Err(Error::Device("mapping a readback buffer failed".into()));
        }
        let view = tmp
            .get_mapped_range(..)
            .map_err(|e| Error::Device(format!("reading back: {e}")))?;
        Ok(view.to_vec())
    }

    /// Positions, velocities and wetness of every point (blocking; tests and diagnostics).
    pub fn read_state(&self) -> Result<Vec<StateGpu>> {
        let bytes = self.read_buffers(&[(&self.state[self.cur], self.points as u64 * 32)], None)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes[..self.points as usize * 32]))
    }
}

/// Decodes the status block (hair status, then water state when `wet`): the status and the
/// particles removed since reset.
pub(super) fn decode_status(w: &[u32], wet: bool) -> (Status, u64) {
    // The hair's 4 status words, then the water's 4 state words.
    let (hair, water) = w.split_at(4);
    let flags = hair[st::FLAGS as usize];
    let status = Status {
        max_speed: f32::from_bits(hair[st::SPEED2 as usize]).sqrt(),
        failed_point: (flags & st::HAIR_NONFINITE != 0).then_some(hair[st::FAILED_POINT as usize]),
        water_failed: flags & st::WATER_NONFINITE != 0,
        particles: if wet { water[ws::HELD as usize] } else { 0 },
    };
    (status, if wet { water[ws::REMOVED as usize] as u64 } else { 0 })
}
