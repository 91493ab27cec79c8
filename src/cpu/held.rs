//! Held water on the CPU backend (docs/WET_MODEL.md §1, §3, §7): each point's water in whole
//! quanta, its capacity, the row parameters with each free point's inverse mass taken from its
//! dry mass plus its water, the drying pass, and the ledger. Exists only when the scene has
//! held water switched on.

use super::avx2::{cpu_has_avx2, run_avx2_or_base};
use super::layout::{Layout, ParamRow, StateRow};
use super::pool::{for_chunks, for_chunks2, Pool};
use super::water::Water;
use crate::engine::WaterLedger;
use crate::params::HeldWater;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::wet;
use glam::Vec3;
use rayon::prelude::*;

/// Blocks per parallel task of the per-point passes.
const BLOCKS_PER_TASK: usize = 32;

/// The held water of every point, per row of 8 lanes.
#[derive(Debug)]
pub struct Held {
    /// Water per point, quanta (0 on padding lanes).
    pub water: Vec<[u32; W]>,
    /// Capacity per point, quanta (0 on padding lanes).
    pub capacity: Vec<[u32; W]>,
    /// Dry mass per point, kg (0 on padding lanes).
    dry_mass: Vec<Lane>,
    /// The layout's row parameters with each free point's inverse mass from its dry mass plus
    /// its water (what the kernel reads instead of the layout's while water is held).
    pub params: Vec<ParamRow>,
    /// Per row: whether its parameters may differ from the layout's (its points, or its bend
    /// springs' far ends, held water at the last refresh). A row that was and is dry is left
    /// as it is: under rain on a large groom most rows are, and rewriting them every step was
    /// most of the pass.
    params_wet: Vec<bool>,
    /// Added and evaporated since the last reset.
    added: u64,
    evaporated: u64,
    cfg: HeldWater,
    /// Velocities at the step's start (flow reads each point's acceleration over the step;
    /// empty unless water flows).
    v0: Vec<L3>,
    /// Scratch of the flow pass, one per task (empty unless water flows).
    flow_tasks: Vec<FlowTask>,
    /// Scratch of the drip pass: per block, the lanes with a point over capacity by a drop.
    drip_lanes: Vec<u8>,
    /// Whether any point may hold water: exact after each step's saturation count, set by a
    /// soaking and by particles that may be absorbed. While false, the per-point passes
    /// (wet_params, flow, drip, dry, saturation) return at once: a scene with the model on
    /// and no water yet (or dried) costs what a dry one does.
    may_hold: bool,
    /// Whether some row's parameters may differ from the layout's (a refresh that saw water).
    params_wet_any: bool,
    /// Whether the per-point passes run compiled for AVX2 ([`cpu_has_avx2`]): their lanes
    /// (the rates' square roots, the divides, the series in f64) then run eight or four wide.
    avx2: bool,
}

/// What one task of the flow pass works in: one block's positions and accelerations.
#[derive(Debug, Default)]
struct FlowTask {
    x: Vec<L3>,
    a: Vec<L3>,
    scratch: wet::FlowScratch,
}

impl Held {
    /// Every point dry, with capacities from the groom's masses.
    pub fn new(lay: &Layout, cfg: HeldWater) -> Held {
        let n_rows = lay.blocks * lay.rows;
        let mut dry_mass = vec![[0.0f32; W]; n_rows];
        let mut capacity = vec![[0u32; W]; n_rows];
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let first = lay.strand_first[s] as usize;
            for i in 0..lay.strand_points(s) {
                let m = lay.mass[first + i];
                dry_mass[b * lay.rows + i][l] = m;
                capacity[b * lay.rows + i][l] = wet::capacity(m, cfg.capacity_ratio);
            }
        }
        let flows = cfg.flows();
        let tasks = if flows { lay.blocks.div_ceil(BLOCKS_PER_TASK) } else { 0 };
        Held {
            water: vec![[0; W]; n_rows],
            capacity,
            dry_mass,
            params: lay.params.clone(),
            params_wet: vec![false; n_rows],
            added: 0,
            evaporated: 0,
            cfg,
            v0: if flows { vec![L3::ZERO; n_rows] } else { Vec::new() },
            flow_tasks: (0..tasks)
                .map(|_| FlowTask {
                    x: Vec::with_capacity(lay.rows),
                    a: Vec::with_capacity(lay.rows),
                    scratch: wet::FlowScratch::default(),
                })
                .collect(),
            drip_lanes: if cfg.drips() { vec![0; lay.blocks] } else { Vec::new() },
            may_hold: false,
            params_wet_any: false,
            avx2: cpu_has_avx2(),
        }
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
        let limp = self.cfg.limp();
        let (water, capacity, dry_mass) = (&self.water, &self.capacity, &self.dry_mass);
        let (rows, ratio, avx2) = (lay.rows, self.cfg.wet_bend_ratio, self.avx2);
        let refresh = |r0: usize, out: &mut [ParamRow], was_wet: &mut [bool]| {
            run_avx2_or_base(
                avx2,
                #[inline(always)]
                || {
                    for (k, (row, was_wet)) in out.iter_mut().zip(was_wet).enumerate() {
                        let (r, i) = (r0 + k, (r0 + k) % rows);
                        let holds = |r: usize| water[r] != [0; W];
                        let wet = holds(r) || (limp && i + 2 < rows && holds(r + 2));
                        if !wet && !*was_wet {
                            continue; // still the layout's values
                        }
                        *was_wet = wet;
                        // Each lane computed, then chosen: branch-free, so the eight lanes' divides
                        // run as vectors (a divide per point was most of the pass).
                        for l in 0..W {
                            let dry_inv = lay.params[r].inv_mass[l];
                            let q = water[r][l];
                            let wet_inv = (1.0 / (dry_mass[r][l] as f64 + wet::to_kg(q))) as f32;
                            row.inv_mass[l] = if dry_inv == 0.0 || q == 0 { dry_inv } else { wet_inv };
                        }
                        if limp && i + 2 < rows {
                            for l in 0..W {
                                let s_a = wet::saturation(water[r][l], capacity[r][l]);
                                let s_b = wet::saturation(water[r + 2][l], capacity[r + 2][l]);
                                let k = lay.params[r].bend.k[l];
                                let wet_k = k * wet::bend_scale(0.5 * (s_a + s_b), ratio);
                                row.bend.k[l] = if s_a + s_b == 0.0 { k } else { wet_k };
                            }
                        }
                    }
                },
            )
        };
        let size = rows * BLOCKS_PER_TASK;
        for_chunks2(pool, &mut self.params, &mut self.params_wet, size, refresh);
    }

    /// Wets every point up to saturation `s` (in [0, 1]) of its capacity; never removes
    /// water. What it adds is booked as added.
    pub fn soak(&mut self, s: f32) {
        for (w, c) in self.water.iter_mut().zip(&self.capacity) {
            for l in 0..W {
                let target = (c[l] as f64 * s as f64).floor() as u32;
                if w[l] < target {
                    self.added += (target - w[l]) as u64;
                    w[l] = target;
                }
            }
        }
        self.may_hold = true;
    }

    /// Keeps the velocities at the step's start, for the flow pass's accelerations.
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

    /// Pass `flow` (§6): held water runs along each strand toward where gravity minus the
    /// point's acceleration over the step points (`wet::flow_strand`, strand by strand).
    pub fn flow(&mut self, lay: &Layout, state: &[StateRow], g: Vec3, dt: f32, pool: Option<&Pool>) {
        if self.v0.is_empty() || !self.may_hold {
            return;
        }
        let (v0, mob, rows, avx2) = (&self.v0, self.cfg.flow_mobility, lay.rows, self.avx2);
        // One task per run of blocks; each block's eight strands flow at once.
        let run = |r0: usize, water: &mut [[u32; W]], t: &mut FlowTask| {
            run_avx2_or_base(
                avx2,
                #[inline(always)]
                || {
                    for (b, water) in water.chunks_mut(rows).enumerate() {
                        if water.iter().all(|w| w.iter().all(|&q| q == 0)) {
                            continue;
                        }
                        let rb = r0 + b * rows;
                        let mut n = [0usize; W];
                        for (l, n) in n.iter_mut().enumerate() {
                            let s = lay.strand_of_slot[(rb / rows) * W + l] as usize;
                            if s < lay.strands {
                                *n = lay.strand_points(s);
                            }
                        }
                        t.x.clear();
                        t.a.clear();
                        for (r, s) in state[rb..rb + rows].iter().enumerate() {
                            t.x.push(s.x);
                            let v0 = &v0[rb + r];
                            let mut a = L3::ZERO;
                            for l in 0..W {
                                a.x[l] = (s.v.x[l] - v0.x[l]) / dt;
                                a.y[l] = (s.v.y[l] - v0.y[l]) / dt;
                                a.z[l] = (s.v.z[l] - v0.z[l]) / dt;
                            }
                            t.a.push(a);
                        }
                        wet::flow_lanes(water, &t.x, &t.a, &n, g, mob, dt, &mut t.scratch);
                    }
                },
            )
        };
        let size = rows * BLOCKS_PER_TASK;
        let (water, tasks) = (&mut self.water, &mut self.flow_tasks);
        match pool {
            Some(pool) => pool.install(|| {
                water
                    .par_chunks_mut(size)
                    .zip(tasks.par_iter_mut())
                    .enumerate()
                    .for_each(|(c, (w, t))| run(c * size, w, t))
            }),
            None => water
                .chunks_mut(size)
                .zip(tasks.iter_mut())
                .enumerate()
                .for_each(|(c, (w, t))| run(c * size, w, t)),
        }
    }

    /// Pass `drip` (§6): a point holding more than its capacity by at least the drip mass,
    /// and from which the water cannot run on along the strand (no neighbour lies along its
    /// effective gravity: a hanging strand's tip, the bottom of a loop, any point when water
    /// does not flow), sheds the excess as a new particle with the point's velocity, `reach`
    /// below it along its effective gravity (where the drop hung as it let go: just out of the
    /// pull of the point it left), strand by strand in the host's order (so the drops are
    /// numbered alike on every run). When the water is full the excess waits.
    #[allow(clippy::too_many_arguments)]
    pub fn drip(
        &mut self,
        lay: &Layout,
        state: &[StateRow],
        g: Vec3,
        dt: f32,
        reach: f32,
        water: &mut Water,
        capacity: usize,
        pool: Option<&Pool>,
    ) {
        if !self.may_hold {
            return;
        }
        let min_drop = wet::to_quanta(self.cfg.drip_mass as f64).max(1);
        // Which lanes of each block hold a drop's excess anywhere, block by block on the pool
        // (rows in memory order); then the strands in the host's order, which numbers the
        // drops, visit only those lanes. Most strands have none: visiting every point in the
        // host's order, a cache miss per strand, was most of the pass.
        let (held, cap, rows) = (&self.water, &self.capacity, lay.rows);
        let mark = |b0: usize, out: &mut [u8]| {
            for (k, lanes) in out.iter_mut().enumerate() {
                let r0 = (b0 + k) * rows;
                let mut m = 0u8;
                for r in r0..r0 + rows {
                    for l in 0..W {
                        m |= ((wet::drip(held[r][l], cap[r][l], min_drop) > 0) as u8) << l;
                    }
                }
                *lanes = m;
            }
        };
        for_chunks(pool, &mut self.drip_lanes, BLOCKS_PER_TASK, mark);
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            if self.drip_lanes[b] & (1 << l) == 0 {
                continue;
            }
            let rows = b * lay.rows..b * lay.rows + lay.strand_points(s);
            for r in rows.clone() {
                let q = wet::drip(self.water[r][l], self.capacity[r][l], min_drop);
                if q == 0 {
                    continue;
                }
                let g_eff = self.g_eff(state, r, l, g, dt);
                if !self.v0.is_empty() && runs_on(state, &rows, r, l, g_eff) {
                    continue;
                }
                let x = state[r].x.get(l) + reach * g_eff.normalize_or_zero();
                if water.add_drop(x, state[r].v.get(l), q, capacity) {
                    self.water[r][l] -= q;
                }
            }
        }
    }

    /// Gravity less the acceleration over the step of lane `l` of row `r` (gravity alone when
    /// water does not flow and no velocities were kept).
    fn g_eff(&self, state: &[StateRow], r: usize, l: usize, g: Vec3, dt: f32) -> Vec3 {
        match self.v0.get(r) {
            Some(v0) => g - (state[r].v.get(l) - v0.get(l)) / dt,
            None => g,
        }
    }

    /// Pass `dry`: each point loses `held (1 - e^(-k dt))` to the nearest quantum, with
    /// `k = (1 / dry_time) (1 + sqrt(|u| / dry_air_speed))` and `u = wind - v` the air
    /// speed past the point. Order-free: integers per point.
    pub fn dry(&mut self, state: &[StateRow], wind: Vec3, dt: f32, pool: Option<&Pool>) {
        if self.cfg.dry_time <= 0.0 || !self.may_hold {
            return;
        }
        let (tau, u_ref, avx2) = (self.cfg.dry_time, self.cfg.dry_air_speed, self.avx2);
        // What a run of rows loses (a sum of integers: the same in any order).
        let dry = |r0: usize, water: &mut [[u32; W]]| -> u64 {
            run_avx2_or_base(
                avx2,
                #[inline(always)]
                || {
                    let mut lost = 0;
                    for (w, r) in water.iter_mut().zip(&state[r0..]) {
                        if w.iter().all(|&q| q == 0) {
                            continue;
                        }
                        // The row's rates as one vector: `(wind - v).length()` component by
                        // component as glam computes it, so the bits are the same.
                        let mut k = [0.0f32; W];
                        for (l, k) in k.iter_mut().enumerate() {
                            let (ux, uy, uz) = (wind.x - r.v.x[l], wind.y - r.v.y[l], wind.z - r.v.z[l]);
                            let u = ((ux * ux) + (uy * uy) + (uz * uz)).sqrt();
                            *k = wet::evaporation_rate(u, tau, u_ref);
                        }
                        let e = wet::evaporate_lanes(w, &k, dt);
                        for l in 0..W {
                            w[l] -= e[l];
                            lost += e[l] as u64;
                        }
                    }
                    lost
                },
            )
        };
        const ROWS: usize = 1024;
        let water = &mut self.water;
        self.evaporated += match pool {
            Some(pool) => pool.install(|| {
                water
                    .par_chunks_mut(ROWS)
                    .enumerate()
                    .map(|(c, w)| dry(c * ROWS, w))
                    .sum::<u64>()
            }),
            None => dry(0, water),
        };
    }

    /// Writes each point's saturation, at most 1, as its wetness, and learns whether any
    /// point holds water (nothing to write when none may: the wetness is already zero).
    pub fn saturation_into(&mut self, wetness: &mut [Lane], pool: Option<&Pool>) {
        if !self.may_hold {
            return;
        }
        let any = std::sync::atomic::AtomicBool::new(false);
        let (water, capacity) = (&self.water, &self.capacity);
        let write = |r0: usize, out: &mut [Lane]| {
            let mut held = false;
            for (k, out) in out.iter_mut().enumerate() {
                held |= water[r0 + k] != [0; W];
                for l in 0..W {
                    out[l] = wet::saturation(water[r0 + k][l], capacity[r0 + k][l]).min(1.0);
                }
            }
            if held {
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

    /// Inverse mass of lane `l` of row `r` (with its water, as this step's kernel reads it).
    pub fn inv_mass(&self, r: usize, l: usize) -> f32 {
        self.params[r].inv_mass[l]
    }

    /// Dry again, with an empty ledger.
    pub fn reset(&mut self, lay: &Layout) {
        self.water.iter_mut().for_each(|w| *w = [0; W]);
        self.added = 0;
        self.evaporated = 0;
        self.may_hold = false;
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
            + self.dry_mass.capacity() * 4 * W
            + self.params.capacity() * std::mem::size_of::<ParamRow>()
            + self.params_wet.capacity()
            + self.v0.capacity() * std::mem::size_of::<L3>()
            + self.drip_lanes.capacity()
    }
}

/// Whether water at row `r` (lane `l`) of a strand on `rows`, under effective gravity `g_eff`,
/// runs on to a neighbour.
fn runs_on(state: &[StateRow], rows: &std::ops::Range<usize>, r: usize, l: usize, g_eff: Vec3) -> bool {
    let x = state[r].x.get(l);
    let toward = |n: usize| wet::runs_toward(g_eff, (state[n].x.get(l) - x).normalize_or_zero());
    (r > rows.start && toward(r - 1)) || (r + 1 < rows.end && toward(r + 1))
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
    }
}
