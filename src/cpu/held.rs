//! Held water on the CPU backend (docs/WET_MODEL.md §1, §3, §7): each point's water in whole
//! quanta, its capacity, the row parameters with each free point's inverse mass taken from its
//! dry mass plus its water, and the ledger. The passes after the substeps are `settle.rs`;
//! the laws per row, `held_rows.rs`. Exists only when the scene has held water switched on.

use super::aligned_rows::AlignedRows;
use super::avx2::{cpu_has_avx2, run_avx2_or_base};
use super::held_rows::{self, BlockScratch, DryRow, ParamSource};
use super::layout::{Layout, ParamRow, StateRow};
use super::pool::{for_chunks, for_chunks2, Pool};
use crate::engine::WaterLedger;
use crate::params::HeldWater;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::wet;

/// Blocks per parallel task of the per-point passes.
pub(super) const BLOCKS_PER_TASK: usize = 32;

/// The held water of every point, per row of 8 lanes.
#[derive(Debug)]
pub struct Held {
    /// Water per point, quanta (0 on padding lanes).
    pub water: AlignedRows<[u32; W]>,
    /// Capacity per point, quanta (0 on padding lanes): the water its fibres take in.
    pub capacity: AlignedRows<[u32; W]>,
    /// Hold limit per point, quanta (0 on padding lanes; `wet::hold_limit`): what it holds
    /// against gravity, in and between its fibres.
    pub hold: AlignedRows<[u32; W]>,
    /// Per row, the dry values the wet parameters are computed from.
    dry: Vec<DryRow>,
    /// Per row, the water one quantum adds to each strand of a point, kg
    /// (`wet::quantum_per_strand` of its bundle); empty without guides, where it is
    /// `WATER_QUANTUM` everywhere.
    quantum: Vec<Lane>,
    /// The layout's row parameters with each free point's inverse mass from its dry mass plus
    /// its water (what the kernel reads instead of the layout's while water is held).
    pub params: Vec<ParamRow>,
    /// Per row: whether its parameters may differ from the layout's (its points, or its bend
    /// springs' far ends, held water at the last refresh). A row that was and is dry is left
    /// as it is: under rain on a large groom most rows are, and rewriting them every step was
    /// most of the pass.
    pub(super) params_wet: Vec<bool>,
    /// Added and evaporated since the last reset.
    added: u64,
    pub(super) evaporated: u64,
    pub(super) cfg: HeldWater,
    /// Velocities at the step's start (flow reads each point's acceleration over the step;
    /// empty unless water flows).
    pub(super) v0: Vec<L3>,
    /// Scratch of the passes after the substeps, one per task of [`BLOCKS_PER_TASK`] blocks.
    pub(super) tasks: Vec<BlockScratch>,
    /// Scratch of the drip pass: per block, the lanes with a point over capacity by a drop.
    pub(super) drip_lanes: Vec<u8>,
    /// Whether any point may hold water: exact after each step's saturation count, set by a
    /// soaking and by particles that may be absorbed. While false, the per-point passes
    /// (wet_params, flow, drip, dry, saturation) return at once: a scene with the model on
    /// and no water yet (or dried) costs what a dry one does.
    pub(super) may_hold: bool,
    /// Whether some row's parameters may differ from the layout's (a refresh that saw water).
    pub(super) params_wet_any: bool,
    /// Whether the pass after the substeps left the parameters and the bridge marks for the
    /// water as it is now (`cpu/settle.rs`); cleared when the host changes the water.
    pub(super) fresh: bool,
    /// Whether the per-point passes run compiled for AVX2 ([`cpu_has_avx2`]): their lanes
    /// (the rates' square roots, the divides, the series in f64) then run eight or four wide.
    pub(super) avx2: bool,
}

impl Held {
    /// Every point dry, with capacities from the groom's masses.
    pub fn new(lay: &Layout, cfg: HeldWater) -> Held {
        let n_rows = lay.blocks * lay.rows;
        let mut dry: Vec<DryRow> = lay
            .params
            .iter()
            .map(|p| DryRow {
                mass: [f32::INFINITY; W],
                bend_k: p.bend.k,
            })
            .collect();
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let first = lay.strand_first[s] as usize;
            for i in 0..lay.strand_points(s) {
                let r = b * lay.rows + i;
                if lay.params[r].inv_mass[l] > 0.0 {
                    dry[r].mass[l] = lay.mass[first + i];
                }
            }
        }
        let flows = cfg.flows();
        let mut held = Held {
            water: AlignedRows::filled([0; W], n_rows),
            capacity: AlignedRows::filled([0u32; W], n_rows),
            hold: AlignedRows::filled([0u32; W], n_rows),
            quantum: Vec::new(),
            dry,
            params: lay.params.clone(),
            params_wet: vec![false; n_rows],
            added: 0,
            evaporated: 0,
            cfg,
            v0: if flows { vec![L3::ZERO; n_rows] } else { Vec::new() },
            tasks: (0..lay.blocks.div_ceil(BLOCKS_PER_TASK))
                .map(|_| BlockScratch::with_rows(lay.rows))
                .collect(),
            drip_lanes: if cfg.drips() { vec![0; lay.blocks] } else { Vec::new() },
            may_hold: false,
            params_wet_any: false,
            fresh: false,
            avx2: cpu_has_avx2(),
        };
        held.set_bundles(lay, &[]);
        held
    }

    /// Sets how many strands' hair each point stands for (`bundle`, per row as the backend
    /// keeps it, `CpuBackend::bundle`; empty: every strand for itself, as without guides): a
    /// point's capacity and hold limit are its bundle's, so a guide holds its followers' water,
    /// and a quantum adds `1 / bundle` of its mass to the strand's own inertia (docs/GUIDES.md
    /// "Water"). The water held stays; the parameters follow at the next step.
    pub fn set_bundles(&mut self, lay: &Layout, bundle: &[Lane]) {
        let cfg = self.cfg;
        self.quantum = bundle.iter().map(|b| b.map(wet::quantum_per_strand)).collect();
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let first = lay.strand_first[s] as usize;
            for i in 0..lay.strand_points(s) {
                let r = b * lay.rows + i;
                let k = bundle.get(r).map_or(1.0, |row| row[l]);
                (self.capacity[r][l], self.hold[r][l]) =
                    wet::bundle_limits(lay.mass[first + i], k, cfg.capacity_ratio, cfg.free_ratio);
            }
        }
        self.params_wet_any = true;
        self.fresh = false;
    }

    /// Each point's water, quanta, in the groom's order (strand after strand).
    pub fn water_of_points(&self, lay: &Layout) -> Vec<u32> {
        let mut out = Vec::with_capacity(lay.mass.len());
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            out.extend((0..lay.strand_points(s)).map(|i| self.water[b * lay.rows + i][l]));
        }
        out
    }

    /// Sets each point's water (quanta, in the groom's order) after the simulation moved
    /// water between points (`physics/bundles.rs`): the ledger books no move, so the total
    /// must be what it was.
    pub fn set_water_of_points(&mut self, lay: &Layout, water: &[u32]) {
        let mut k = 0;
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            for i in 0..lay.strand_points(s) {
                self.water[b * lay.rows + i][l] = water[k];
                k += 1;
            }
        }
        self.may_hold = true;
        self.params_wet_any = true;
        self.fresh = false;
    }

    /// Pass `wet_params` (once per step, before the substeps): sets each free point's inverse
    /// mass to `1 / (dry + water)` (soaked hair is heavier, §3) and, when limp, scales each
    /// bend spring's stiffness by `wet::bend_scale` of the mean saturation of its two ends
    /// (§4). A dry point and a dry spring keep the layout's values bit for bit.
    pub fn refresh_params(&mut self, lay: &Layout, pool: Option<&Pool>) {
        if !self.may_hold && !self.params_wet_any {
            return; // every row holds the layout's values
        }
        self.params_wet_any = self.may_hold;
        // The rows written, out of `self` while the law reads its constants.
        let (mut params, mut was_wet) = (std::mem::take(&mut self.params), std::mem::take(&mut self.params_wet));
        let src = self.param_source(lay);
        let (water, avx2) = (&self.water, self.avx2);
        let refresh = |r0: usize, out: &mut [ParamRow], was_wet: &mut [bool]| {
            run_avx2_or_base(
                avx2,
                #[inline(always)]
                || {
                    let (w, c) = (&water[r0..r0 + out.len()], &src.capacity[r0..]);
                    held_rows::refresh_rows(&src, r0, w, |k| wet::saturation_lanes(&w[k], &c[k]), out, was_wet)
                },
            )
        };
        let size = lay.rows * BLOCKS_PER_TASK;
        for_chunks2(pool, &mut params, &mut was_wet, size, refresh);
        (self.params, self.params_wet) = (params, was_wet);
    }

    /// What the wet parameters are computed from.
    pub(super) fn param_source<'a>(&'a self, lay: &'a Layout) -> ParamSource<'a> {
        ParamSource {
            rows: lay.rows,
            dry: &self.dry,
            quantum: &self.quantum,
            capacity: &self.capacity,
            hold: &self.hold,
            limp: self.cfg.limp(),
            ratio: self.cfg.wet_bend_ratio,
        }
    }

    /// Whether the pass after the last step left this step's parameters and bridge marks
    /// (nothing changed the water since); the flag is cleared, so it answers once.
    pub fn take_fresh(&mut self) -> bool {
        std::mem::take(&mut self.fresh)
    }

    /// Wets every point up to `s` times its hold limit ([`wet::soak_target`]); never removes
    /// water. What it adds is booked as added.
    pub fn soak(&mut self, s: f32) {
        for (w, c) in self.water.iter_mut().zip(&self.hold) {
            for l in 0..W {
                let target = wet::soak_target(c[l], s);
                if w[l] < target {
                    self.added += (target - w[l]) as u64;
                    w[l] = target;
                }
            }
        }
        self.may_hold = true;
        self.fresh = false;
    }

    /// Keeps the velocities at the step's start, for the flow pass's accelerations (unless
    /// the pass after the last step's substeps kept them: [`Held::take_fresh`]).
    pub fn keep_velocities(&mut self, state: &[StateRow], pool: Option<&Pool>) {
        if !self.may_hold {
            return;
        }
        let copy = |r0: usize, out: &mut [L3]| {
            for (v0, r) in out.iter_mut().zip(&state[r0..]) {
                *v0 = r.v;
            }
        };
        for_chunks(pool, &mut self.v0, 4096, copy);
    }

    /// The state changed outside a step (a reset, strands seeded or carried): the velocities
    /// kept for the next step no longer hold.
    pub fn state_changed(&mut self) {
        self.fresh = false;
    }

    /// Writes each point's wetness (its water over its hold limit, at most 1), and learns
    /// whether any point holds water (nothing to write when none may: the wetness is already
    /// zero).
    pub fn saturation_into(&mut self, wetness: &mut [Lane], pool: Option<&Pool>) {
        if !self.may_hold {
            return;
        }
        let any = std::sync::atomic::AtomicBool::new(false);
        let (water, capacity, hold) = (&self.water, &self.capacity, &self.hold);
        let write = |r0: usize, out: &mut [Lane]| {
            let n = out.len();
            let r = r0..r0 + n;
            if held_rows::saturation_rows(&water[r.clone()], &capacity[r.clone()], &hold[r], out, None) {
                any.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        };
        for_chunks(pool, wetness, 1024, write);
        self.may_hold = any.into_inner();
    }

    /// Particles are in the simulation this step: the hair may absorb some.
    pub fn may_absorb(&mut self) {
        self.may_hold = true;
    }

    /// Whether any point may hold water now.
    pub fn may_hold(&self) -> bool {
        self.may_hold
    }

    /// The row parameters the kernel reads: the layout's with each point's water.
    pub fn row_params(&self) -> &[ParamRow] {
        &self.params
    }

    /// Dry again, with an empty ledger.
    pub fn reset(&mut self, lay: &Layout) {
        self.water.iter_mut().for_each(|w| *w = [0; W]);
        self.added = 0;
        self.evaporated = 0;
        self.may_hold = false;
        self.fresh = false;
        self.refresh_params(lay, None);
    }

    /// The ledger's hair side, in quanta: added by soaking, held, evaporated (the particles'
    /// side is added by the caller).
    pub fn ledger(&self) -> WaterLedger {
        WaterLedger {
            added: self.added,
            held: self.water.iter().flatten().map(|&q| q as u64).sum(),
            evaporated: self.evaporated,
            ..WaterLedger::default()
        }
    }

    /// Bytes held (what a scene with held water costs).
    pub fn bytes(&self) -> usize {
        self.water.capacity() * 4 * W
            + self.capacity.capacity() * 4 * W
            + self.hold.capacity() * 4 * W
            + self.dry.capacity() * std::mem::size_of::<DryRow>()
            + self.quantum.capacity() * 4 * W
            + self.params.capacity() * std::mem::size_of::<ParamRow>()
            + self.params_wet.capacity()
            + self.v0.capacity() * std::mem::size_of::<L3>()
            + self.drip_lanes.capacity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::SimParams;

    /// Every field as printed: the shortest text that reads back to the same float, so equal
    /// text is equal bits (no NaN here).
    fn bits(p: &[ParamRow]) -> String {
        format!("{p:?}")
    }

    /// Rows that were and are dry are skipped by `wet_params`; a row that dries goes back to
    /// the layout's values bit for bit, and a wet one changes.
    #[test]
    fn wet_params_returns_dried_rows_to_the_layout() {
        let groom = crate::groom::paper_scene(40, 6).unwrap();
        let params = SimParams {
            held_water: HeldWater::ON,
            ..SimParams::paper()
        };
        let lay = Layout::new(&groom, &params);
        let mut held = Held::new(&lay, params.held_water);
        held.refresh_params(&lay, None);
        assert_eq!(bits(&held.params), bits(&lay.params), "dry");
        held.water[lay.rows + 3][2] = held.capacity[lay.rows + 3][2];
        held.may_absorb(); // water arrived as absorption brings it
        held.refresh_params(&lay, None);
        assert_ne!(bits(&held.params), bits(&lay.params), "wet");
        assert_ne!(
            held.params[lay.rows + 3].inv_mass[2],
            lay.params[lay.rows + 3].inv_mass[2]
        );
        held.water[lay.rows + 3][2] = 0;
        held.refresh_params(&lay, None);
        assert_eq!(bits(&held.params), bits(&lay.params), "dried");
        // Every point soaked, pinned roots and padding lanes too: those keep an inverse
        // mass of 0 (their dry record's mass is infinite), the others grow heavier.
        let groom = crate::groom::paper_scene(13, 6).unwrap();
        let lay = Layout::new(&groom, &params);
        let mut held = Held::new(&lay, params.held_water);
        for (w, c) in held.water.iter_mut().zip(&held.capacity) {
            *w = c.map(|c| c.max(1));
        }
        held.may_absorb();
        held.refresh_params(&lay, None);
        let (mut fixed, mut free) = (0, 0);
        for (wet, dry) in held.params.iter().zip(&lay.params) {
            for l in 0..W {
                if dry.inv_mass[l] == 0.0 {
                    assert_eq!(wet.inv_mass[l].to_bits(), 0, "a pinned or padding lane stays fixed");
                    fixed += 1;
                } else {
                    assert!(wet.inv_mass[l] < dry.inv_mass[l] && wet.inv_mass[l] > 0.0);
                    free += 1;
                }
            }
        }
        // 13 roots, and 3 padding lanes of the second block's 6 rows.
        assert!(
            fixed >= 13 + 3 * 6 && free > 0,
            "pinned points and padding lanes were tried"
        );
    }
}
