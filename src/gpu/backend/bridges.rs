//! Liquid bridges on the GPU (docs/WET_MODEL.md §5; `shaders/bridges.wgsl`, pass hair_grid,
//! and `shaders/cohesion.wgsl`, pass cohesion): the hashed grid of wet points, each point's
//! nearest and bridges, the kernels' encoding and the search turn. Exists only when the scene
//! has bridges (held water with `bridge_tension > 0`).

use super::super::buffers::{self as b, bridge_words, groups, SCAN_BLOCK, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use crate::physics::wet::BRIDGE_SEARCH_TURNS;

/// Pass hair_grid's kernels, in order.
pub(super) const BRIDGE_ENTRIES: [&str; 9] = [
    "bridge_count",
    "bridge_scan_blocks",
    "bridge_scan_sums",
    "bridge_scan_add",
    "bridge_scatter",
    "bridge_search_setup",
    "bridge_search",
    "bridge_pairs",
    "bridge_coef",
];

/// What the bridge kernels read of held water: the water per point and its capacity.
pub(super) struct HeldBuffers<'a> {
    pub(super) water: &'a wgpu::Buffer,
    pub(super) capacity: &'a wgpu::Buffer,
}

/// The liquid bridges' buffers and pipelines.
#[derive(Debug)]
pub(super) struct BridgesGpu {
    /// Wet points per bucket, and the points listed to search (zero between builds).
    count: wgpu::Buffer,
    /// Bucket starts, scan block sums, entries, the list of searching points (`bridges.wgsl`).
    bucket: wgpu::Buffer,
    /// The search's indirect dispatch size, written by `bridge_search_setup`.
    search_dispatch: wgpu::Buffer,
    /// `search_dispatch` as storage (bridge_search_setup only).
    dispatch_bg: wgpu::BindGroup,
    /// Per point: nearest, bridges and coefficients (`buffers::bridge_words`).
    bridge: wgpu::Buffer,
    /// Scan blocks of the bucket table.
    blocks: u32,
    /// Buckets of the table, and the points it is made for.
    buckets: u32,
    points: u32,
    /// Group 0 over state A and B.
    bg: [wgpu::BindGroup; 2],
    /// Group 3 of the hair module's cohesion kernel (the bridge records), and its layout.
    pub(super) cohesion_layout: wgpu::BindGroupLayout,
    pub(super) cohesion_bg: wgpu::BindGroup,
    pipes: Vec<wgpu::ComputePipeline>,
    /// Steps since the last reset (whose search turn it is).
    step: u32,
}

impl BridgesGpu {
    /// Buffers and pipelines for `points` points: the step parameters, the point records the
    /// hair reads (with the water's mass), held water's buffers and the two state buffers.
    pub(super) fn new(
        d: &wgpu::Device,
        consts: SceneConsts,
        points: u32,
        params: &wgpu::Buffer,
        points_wet: &wgpu::Buffer,
        held: HeldBuffers,
        state: &[wgpu::Buffer; 2],
    ) -> BridgesGpu {
        // About two buckets per point, as the CPU's grid keeps for its wet points (here for
        // all, so the table never grows), and whole scan blocks.
        let buckets = (2 * points).next_power_of_two().max(SCAN_BLOCK);
        let blocks = buckets / SCAN_BLOCK;
        let count = b::buffer(d, "bridge_count", (buckets as u64 + 1) * 4, STORAGE);
        // Starts, block sums, entries, then the search list's length and the list.
        let bucket = b::buffer(
            d,
            "bridge_bucket",
            (buckets as u64 + 1 + blocks as u64 + 2 * points as u64 + 1) * 4,
            STORAGE,
        );
        let search_dispatch = b::buffer(d, "bridge_dispatch", 16, STORAGE | wgpu::BufferUsages::INDIRECT);
        let dispatch_layout = pl::layout(d, "bridge dispatch", &[Slot::ReadWrite]);
        let dispatch_bg = pl::bind(d, "bridge dispatch", &dispatch_layout, &[&search_dispatch], None);
        let bridge = b::buffer(d, "bridge", points as u64 * bridge_words::PER_POINT as u64 * 4, STORAGE);
        use Slot::*;
        let layout = pl::layout(
            d,
            "bridges",
            &[Uniform, Read, Read, Read, Read, ReadWrite, ReadWrite, ReadWrite],
        );
        let mk = |i: usize| {
            pl::bind(
                d,
                "bridges",
                &layout,
                &[
                    params,
                    points_wet,
                    held.water,
                    held.capacity,
                    &state[i],
                    &count,
                    &bucket,
                    &bridge,
                ],
                None,
            )
        };
        let bg = [mk(0), mk(1)];
        let cohesion_layout = pl::layout(d, "cohesion", &[Read]);
        let cohesion_bg = pl::bind(d, "cohesion", &cohesion_layout, &[&bridge], None);
        let module = pl::module(d, "bridges", &pl::bridges_source(consts, buckets, points));
        // Only the setup binds group 1: the other kernels leave whatever an earlier pass set
        // there (the held-water passes bind theirs) out of their layouts.
        let pipes = BRIDGE_ENTRIES
            .iter()
            .flat_map(|&e| match e {
                "bridge_search_setup" => pl::pipelines(d, &module, &[&layout, &dispatch_layout], &[e]),
                _ => pl::pipelines(d, &module, &[&layout], &[e]),
            })
            .collect();
        BridgesGpu {
            count,
            bucket,
            search_dispatch,
            dispatch_bg,
            bridge,
            blocks,
            buckets,
            points,
            bg,
            cohesion_layout,
            cohesion_bg,
            pipes,
            step: 0,
        }
    }

    /// The buffer of bucket starts, entries and the list of searching points.
    pub(super) fn bucket(&self) -> &wgpu::Buffer {
        &self.bucket
    }

    /// The word of `bucket` that holds how many points searched in the last step
    /// (`bridges.wgsl` `B_SEARCHES`: after the starts, the block sums and the entries).
    pub(super) fn searches_word(&self) -> u64 {
        (self.buckets + 1 + self.blocks + self.points) as u64
    }

    /// This step's search turn (`wet::bridge_search_turn`), as the step parameters carry it.
    pub(super) fn turn(&self) -> u32 {
        self.step % BRIDGE_SEARCH_TURNS
    }

    /// Pass hair_grid over state `cur` (the step's start), after wet_params; the next step
    /// takes the next turn.
    pub(super) fn encode(&mut self, pass: &mut wgpu::ComputePass, cur: usize, points: u32) {
        let (gx, gy) = groups(points);
        pass.set_bind_group(0, &self.bg[cur], &[]);
        for (k, p) in self.pipes.iter().enumerate() {
            pass.set_pipeline(p);
            match BRIDGE_ENTRIES[k] {
                "bridge_scan_blocks" | "bridge_scan_add" => pass.dispatch_workgroups(self.blocks, 1, 1),
                "bridge_scan_sums" => pass.dispatch_workgroups(1, 1, 1),
                "bridge_search_setup" => {
                    pass.set_bind_group(1, &self.dispatch_bg, &[]);
                    pass.dispatch_workgroups(1, 1, 1)
                }
                // Over the listed points only (about an eighth), not all.
                "bridge_search" => pass.dispatch_workgroups_indirect(&self.search_dispatch, 0),
                _ => pass.dispatch_workgroups(gx, gy, 1),
            }
        }
        self.step = self.step.wrapping_add(1);
    }

    /// No bridges, nothing found, and the turns start over (a reset simulation replays like
    /// a new one).
    pub(super) fn reset(&mut self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.bridge, 0, None);
        enc.clear_buffer(&self.count, 0, None);
        self.step = 0;
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        (self.count.size() + self.bucket.size() + self.bridge.size() + self.search_dispatch.size()) as usize
    }
}
