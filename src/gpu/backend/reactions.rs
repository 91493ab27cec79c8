//! Eq. 2's reactions gathered by the particles (`SceneConsts::gathered`): the `wet_order`
//! buffer and the pipelines of `reactions.wgsl`, encoded after each substep's hair kernel.
//! The hair kernel leaves a record for each point with a particle within reach
//! (`reaction_gathered.wgsl`); these passes sort the records by water-grid bucket and let
//! each particle sum its pairs, with no atomic add per pair.

use super::super::buffers::{groups, wet_words};
use super::super::pipelines::{self as pl, SceneConsts, Slot};

/// Entry points of `reactions.wgsl`, in their order within a substep.
const ENTRIES: [&str; 5] = [
    "react_scan_blocks",
    "react_scan_sums",
    "react_scan_add",
    "react_scatter",
    "react_gather",
];

/// The gather's buffer, pipelines and bind groups (one per particle buffer).
#[derive(Debug)]
pub(super) struct ReactionsGpu {
    /// The records' bucket starts, the prefix sum's block sums, their indices in bucket order.
    order: wgpu::Buffer,
    pipes: Vec<wgpu::ComputePipeline>,
    /// By `WaterGpu::cur`: the particles the hair kernel read (the other buffer).
    bg: [wgpu::BindGroup; 2],
}

impl ReactionsGpu {
    /// Buffers and pipelines for `points` hair points and a water grid of at most
    /// `max_buckets` buckets. `wet` holds the sums, counts and records; `particles` are both
    /// particle buffers; `absorb` is absorption's scratch (or its placeholder).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        d: &wgpu::Device,
        consts: SceneConsts,
        params: &wgpu::Buffer,
        particles: &[wgpu::Buffer; 2],
        grid: &wgpu::Buffer,
        wet: &wgpu::Buffer,
        absorb: &wgpu::Buffer,
        points: u32,
        max_buckets: u32,
    ) -> ReactionsGpu {
        let order = super::super::buffers::buffer(
            d,
            "wet_order",
            wet_words::order_words(max_buckets, points) * 4,
            super::super::buffers::STORAGE,
        );
        let layout = pl::layout(
            d,
            "reactions",
            &[
                Slot::Uniform,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::ReadWrite,
            ],
        );
        let module = pl::module(d, "reactions", &pl::reactions_source(consts));
        let pipes = pl::pipelines(d, &module, &[&layout], &ENTRIES);
        let mk = |i: usize| {
            pl::bind(
                d,
                "reactions",
                &layout,
                &[params, &particles[1 - i], grid, wet, &order, absorb],
                None,
            )
        };
        ReactionsGpu {
            bg: [mk(0), mk(1)],
            order,
            pipes,
        }
    }

    /// Encodes one substep's passes after the hair kernel: the prefix sum over the buckets
    /// (sized by the water grid's `dispatch`, written by its setup), the records' scatter
    /// over the `points` active points, and the gather over the `bound` particle slots.
    /// Leaves bind group 0 set to its own: the caller sets its own again.
    pub(super) fn encode(
        &self,
        pass: &mut wgpu::ComputePass,
        cur: usize,
        dispatch: &wgpu::Buffer,
        points: u32,
        bound: u32,
    ) {
        pass.set_bind_group(0, &self.bg[cur], &[]);
        for (p, e) in self.pipes.iter().zip(ENTRIES) {
            pass.set_pipeline(p);
            match e {
                "react_scan_blocks" | "react_scan_add" => pass.dispatch_workgroups_indirect(dispatch, 0),
                "react_scan_sums" => pass.dispatch_workgroups(1, 1, 1),
                "react_scatter" => {
                    let (gx, gy) = groups(points);
                    pass.dispatch_workgroups(gx, gy, 1)
                }
                _ => {
                    let (gx, gy) = groups(bound.max(1));
                    pass.dispatch_workgroups(gx, gy, 1)
                }
            }
        }
    }

    /// Bytes the gather holds beyond the `wet` buffer (`GpuBackend::buffer_sizes`).
    pub(super) fn order_bytes(&self) -> usize {
        self.order.size() as usize
    }
}
