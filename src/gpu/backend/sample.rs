//! The error budget's sampled points, read one step behind: each step copies the sampled
//! strands' states into one of two staging buffers after its passes, and the next step's
//! budget reads the older one, which the device finished a step ago, so the budget does not
//! wait for the step it just submitted.

use super::readback::Staging;
use super::GpuBackend;
use crate::error::{Error, Result};
use glam::Vec3;
use std::sync::atomic::Ordering;

/// Bytes of one point's state record (`StateGpu`: position then velocity, four floats each).
const STATE_BYTES: u64 = 32;

/// The sampled points and their staging ring.
#[derive(Debug)]
pub(super) struct Sample {
    /// Runs of consecutive points (first, count), in the order asked for.
    runs: Vec<(u32, u32)>,
    ring: [Staging; 2],
}

/// Consecutive indices as runs (first, count).
fn runs_of(idx: &[u32]) -> Vec<(u32, u32)> {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for &i in idx {
        match runs.last_mut() {
            Some((first, count)) if *first + *count == i => *count += 1,
            _ => runs.push((i, 1)),
        }
    }
    runs
}

impl GpuBackend {
    /// Copies the states of the points `idx` (host order) at the end of every step from now
    /// on, for [`GpuBackend::sampled_behind`].
    pub fn sample_every_step(&mut self, idx: &[u32]) {
        let bytes = (idx.len() as u64 * STATE_BYTES).max(STATE_BYTES);
        let d = &self.dev.device;
        self.sample = Some(Sample {
            runs: runs_of(idx),
            ring: [Staging::new(d, "sample", bytes), Staging::new(d, "sample", bytes)],
        });
    }

    /// Encodes this step's copy into the ring slot of step `self.frame` (after the step's
    /// passes; the state is `self.cur`).
    pub(super) fn encode_sample(&mut self, enc: &mut wgpu::CommandEncoder) {
        let Some(s) = &mut self.sample else { return };
        let slot = &mut s.ring[(self.frame % 2) as usize];
        slot.settle(&self.dev.device);
        let mut at = 0;
        for &(first, count) in &s.runs {
            let len = count as u64 * STATE_BYTES;
            enc.copy_buffer_to_buffer(
                &self.state[self.cur],
                first as u64 * STATE_BYTES,
                &slot.buf,
                at,
                Some(len),
            );
            at += len;
        }
    }

    /// Maps this step's slot once its copy is submitted.
    pub(super) fn map_sample(&mut self) {
        if let Some(s) = &mut self.sample {
            s.ring[(self.frame % 2) as usize].map(self.frame);
        }
    }

    /// The sampled points' positions at the end of the step before the last into `out`
    /// (cleared first): waits only if the device has not finished that step. `Ok(false)`
    /// when there is no such step (the first since create or reset).
    pub fn sampled_behind(&mut self, out: &mut Vec<Vec3>) -> Result<bool> {
        let Some(s) = &mut self.sample else { return Ok(false) };
        let Some(behind) = self.frame.checked_sub(1) else {
            return Ok(false);
        };
        let slot = &mut s.ring[(behind % 2) as usize];
        if slot.frame != Some(behind) {
            return Ok(false);
        }
        while !slot.ready.load(Ordering::Acquire) {
            self.dev.wait()?;
            if !slot.ready.load(Ordering::Acquire) {
                self.dev.check()?;
                return Err(Error::Device("mapping the sampled points failed".into()));
            }
        }
        out.clear();
        {
            let view = slot
                .buf
                .get_mapped_range(..)
                .map_err(|e| Error::Device(format!("reading the sampled points: {e}")))?;
            let words: &[f32] = bytemuck::cast_slice(&view);
            let points: usize = s.runs.iter().map(|r| r.1 as usize).sum();
            out.extend((0..points).map(|p| Vec3::from_slice(&words[8 * p..8 * p + 3])));
        }
        slot.settle(&self.dev.device);
        Ok(true)
    }

    /// Forgets the sampled steps (a reset).
    pub(super) fn reset_sample(&mut self) {
        if let Some(s) = &mut self.sample {
            for slot in &mut s.ring {
                slot.settle(&self.dev.device);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn consecutive_points_make_one_run() {
        assert_eq!(super::runs_of(&[0, 1, 2, 10, 11, 20]), vec![(0, 3), (10, 2), (20, 1)]);
        assert!(super::runs_of(&[]).is_empty());
    }
}
