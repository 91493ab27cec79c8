//! Per-stage GPU time ([`crate::Simulation::time_passes`] on the GPU backend): inside the
//! step's compute pass a timestamp opens the step and one closes each stage (the stages of
//! [`crate::timers`], the names the CPU's timers use); after the step they are resolved, read
//! back and each interval booked to the stage it closes. Each timed step therefore waits for
//! the GPU: a measuring mode, not a shipping one. Needs the adapter's timestamps inside passes
//! (`TIMESTAMP_QUERY_INSIDE_PASSES`); nothing of it exists until a host switches it on, and
//! off, a stage's end costs one branch while encoding.

use super::super::buffers as b;
use crate::timers::{Stage, StageClock};
use std::time::Duration;

/// The query set, its resolve buffer and the stages this step's timestamps close.
#[derive(Debug)]
pub(super) struct PassStamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// Timestamps the set holds: enough for every stage of a step (see [`PassStamps::new`]).
    capacity: u32,
    /// Per timestamp after the first: the stage it closes.
    closes: Vec<Stage>,
    /// Nanoseconds per timestamp tick.
    period_ns: f32,
    /// Totals per stage since timing was switched on.
    pub(super) clock: StageClock,
}

impl PassStamps {
    /// Room for a step of `n_sub` substeps: the opening stamp, up to five stages before the
    /// substeps (wet_params, hair_grid, volume, the new particles' insertion), up to six in each
    /// (water_grid, cohesion, blocks, the SDF colliders' part of blocks, absorb,
    /// water_integrate) and up to four after (flow, drip, dry, water_cull).
    pub(super) fn new(d: &wgpu::Device, q: &wgpu::Queue, n_sub: usize) -> PassStamps {
        let capacity = (1 + 5 + 6 * n_sub + 4) as u32;
        let mut clock = StageClock::default();
        clock.set(true);
        PassStamps {
            queries: d.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            }),
            resolve: b::buffer(
                d,
                "stage timestamps",
                8 * capacity as u64,
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            capacity,
            closes: Vec::with_capacity(capacity as usize),
            period_ns: q.get_timestamp_period(),
            clock,
        }
    }

    /// The step's opening stamp.
    pub(super) fn open(&mut self, pass: &mut wgpu::ComputePass) {
        self.closes.clear();
        pass.write_timestamp(&self.queries, 0);
    }

    /// Closes `stage`: the time since the last stamp is its.
    fn close(&mut self, pass: &mut wgpu::ComputePass, stage: Stage) {
        let k = self.closes.len() as u32 + 1;
        debug_assert!(k < self.capacity, "more stages than PassStamps::new counted");
        if k < self.capacity {
            pass.write_timestamp(&self.queries, k);
            self.closes.push(stage);
        }
    }

    /// Resolves this step's stamps into the resolve buffer (after the compute pass).
    pub(super) fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        enc.resolve_query_set(&self.queries, 0..self.closes.len() as u32 + 1, &self.resolve, 0);
    }

    /// The resolve buffer and how many of its bytes this step wrote.
    pub(super) fn resolved(&self) -> (&wgpu::Buffer, u64) {
        (&self.resolve, 8 * (self.closes.len() as u64 + 1))
    }

    /// Books the resolved stamps (`bytes` from [`PassStamps::resolved`]) to their stages.
    pub(super) fn book(&mut self, bytes: &[u8]) {
        let n = self.closes.len() + 1;
        let stamps: Vec<u64> = bytes[..8 * n]
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        for (k, &stage) in self.closes.iter().enumerate() {
            let ticks = stamps[k + 1].saturating_sub(stamps[k]);
            self.clock.add(
                stage,
                Duration::from_nanos((ticks as f64 * self.period_ns as f64) as u64),
            );
        }
    }
}

/// Closes `stage` when stage timing is on (one branch when off).
#[inline]
pub(super) fn close(stamps: &mut Option<PassStamps>, pass: &mut wgpu::ComputePass, stage: Stage) {
    if let Some(s) = stamps {
        s.close(pass, stage);
    }
}
