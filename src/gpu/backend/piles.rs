//! Drops that meet coalesce on the GPU (`piles.wgsl`; `cpu/piles.rs` on the CPU): the table
//! that groups a step's drops by pile cell, each drop's slot in it, and the passes that make
//! the sources at the step's start and hand their places back to the drops at its end. Made
//! with the water buffers, only where `SimParams::coalesces`.

use super::super::buffers::{self as b, groups, pile_words, STORAGE};
use super::super::device::GpuDevice;
use super::super::pipelines::{self as pl, SceneConsts, Slot};

/// The entry points of `piles.wgsl`, in the order they run: [`PILE_GROUP`] of them at a step's
/// start, the rest at its end.
const PILE_ENTRIES: [&str; 7] = [
    "pile_clear",
    "pile_insert",
    "pile_sources",
    "pile_finish",
    "pile_spread_sources",
    "pile_spread_drops",
    "pile_spread_finish",
];

/// How many of [`PILE_ENTRIES`] group the drops (the rest spread the sources back).
const PILE_GROUP: usize = 4;

/// The table, the drops' slots, their bind groups and the passes.
#[derive(Debug)]
pub(super) struct PilesGpu {
    /// Bind groups: [cur = A, other = B], [cur = B, other = A].
    bg: [wgpu::BindGroup; 2],
    /// Pipelines by entry point ([`PILE_ENTRIES`]).
    pipes: Vec<wgpu::ComputePipeline>,
    /// Bytes of the table and the slots (the water buffers' report).
    bytes: u64,
}

impl PilesGpu {
    /// The table and slots for `capacity` drops, bound with the particle buffers, the water
    /// state and the grid (whose header takes the largest pile).
    pub(super) fn new(
        dev: &GpuDevice,
        consts: SceneConsts,
        params: &wgpu::Buffer,
        particles: &[wgpu::Buffer; 2],
        state: &wgpu::Buffer,
        grid: &wgpu::Buffer,
        capacity: u32,
    ) -> PilesGpu {
        let d = &dev.device;
        let table_bytes = pile_words::slots(capacity) as u64 * pile_words::WORDS as u64 * 4;
        let table = b::buffer(d, "pile_table", table_bytes, STORAGE);
        let slot_bytes = capacity.max(1) as u64 * 4;
        let slots = b::buffer(d, "pile_slot", slot_bytes, STORAGE);
        let mut kinds = vec![Slot::Uniform];
        kinds.extend([Slot::ReadWrite; 6]);
        let layout = pl::layout(d, "piles", &kinds);
        let mk = |i: usize| {
            pl::bind(
                d,
                "piles",
                &layout,
                &[params, &particles[i], &particles[1 - i], state, grid, &table, &slots],
                None,
            )
        };
        let module = pl::module(d, "piles", &pl::piles_source(consts));
        let pipes = pl::pipelines(d, &module, &[&layout], &PILE_ENTRIES);
        PilesGpu {
            bg: [mk(0), mk(1)],
            pipes,
            bytes: table_bytes + slot_bytes,
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Encodes the step's grouping over at most `bound` drops in `particles[*cur]`: the sources
    /// go to the other buffer, which becomes `cur`.
    pub(super) fn encode_group(&self, pass: &mut wgpu::ComputePass, cur: &mut usize, bound: u32) {
        self.encode(pass, *cur, 0..PILE_GROUP, bound);
        *cur = 1 - *cur;
    }

    /// Encodes the step's end: each drop takes its source's place and velocity, into the other
    /// buffer, which becomes `cur`.
    pub(super) fn encode_spread(&self, pass: &mut wgpu::ComputePass, cur: &mut usize, bound: u32) {
        self.encode(pass, *cur, PILE_GROUP..PILE_ENTRIES.len(), bound);
        *cur = 1 - *cur;
    }

    /// Encodes the entries `run` of [`PILE_ENTRIES`] on the bind group for `particles[cur]`.
    fn encode(&self, pass: &mut wgpu::ComputePass, cur: usize, run: std::ops::Range<usize>, bound: u32) {
        pass.set_bind_group(0, &self.bg[cur], &[]);
        for k in run {
            pass.set_pipeline(&self.pipes[k]);
            // The table's passes cover its slots for `bound` drops; the others the drops; the
            // finishing ones run once.
            let (gx, gy) = match PILE_ENTRIES[k] {
                "pile_finish" | "pile_spread_finish" => (1, 1),
                "pile_clear" | "pile_sources" => groups(pile_words::slots(bound)),
                _ => groups(bound.max(1)),
            };
            pass.dispatch_workgroups(gx, gy, 1);
        }
    }
}
