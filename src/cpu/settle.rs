//! The held water's passes after the substeps, on the CPU: `flow`, `drip` and `dry`, then the
//! saturation the vertices show, and the next step's `wet_params` and liquid-bridge marks.
//! Each is a sweep over the groom's rows on the GPU; here they run block by block while the
//! block is in cache (as the block kernel runs the per-point passes), in the pass list's
//! order for each block. The one pass that couples blocks is `drip`: it numbers the drops
//! strand by strand in the host's order. So a block that sheds no drop (nearly all) is
//! finished in the same sweep, right after its flow; the few that shed one wait, and are
//! finished after the serial drip. The water comes out as if every pass had swept the whole
//! groom in turn: each law reads only its own block's water.
//!
//! Run one after another, the sweeps read the big groom's water, capacities, velocities and
//! parameters five times a step (17 ms of a 70 ms step under rain on 2 threads).

use super::aligned_rows::AlignedRows;
use super::avx2::run_avx2_or_base as avx2;
use super::held::Held;
use super::held_rows::{self, BlockScratch, DryLaw, ParamSource};
use super::layout::{Layout, ParamRow, StateRow};
use super::pool::{chunks_or_empty, Pool};
use super::water::Water;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::wet;
use crate::timers::{Stage, StageClock};
use glam::Vec3;
use rayon::prelude::*;

/// Where the drip pass puts the drops it makes.
pub struct DropSink<'a> {
    pub water: &'a mut Water,
    /// How far below the point a drop starts, m.
    pub reach: f32,
    /// The most particles the simulation holds.
    pub capacity: usize,
}

/// What the pass writes besides the water.
pub struct SettleOut<'a> {
    /// Per row, the saturation shown as wetness.
    pub wetness: &'a mut [Lane],
    /// With liquid bridges: per row, the free lanes, and the next step's marks to write.
    pub bridges: Option<(&'a [u8], &'a mut [u8])>,
}

/// One task's share of the per-row outputs: its run of blocks' rows.
struct Rows<'a> {
    water: &'a mut [[u32; W]],
    params: &'a mut [ParamRow],
    was_wet: &'a mut [bool],
    wetness: &'a mut [Lane],
    marks: &'a mut [u8],
    /// The velocities kept for the next step's flow (empty when water does not flow).
    v0: &'a mut [L3],
}

impl Rows<'_> {
    /// Block `j` of the run (`rows` rows a block); marks are empty without bridges.
    fn block(&mut self, j: usize, rows: usize) -> Rows<'_> {
        let r = j * rows..(j + 1) * rows;
        Rows {
            water: &mut self.water[r.clone()],
            params: &mut self.params[r.clone()],
            was_wet: &mut self.was_wet[r.clone()],
            wetness: &mut self.wetness[r.clone()],
            marks: self.marks.get_mut(r.clone()).unwrap_or_default(),
            v0: self.v0.get_mut(r).unwrap_or_default(),
        }
    }
}

/// The per-row buffers of [`Held`] the pass writes, taken out of it while the laws read
/// its constants (and put back).
struct Bufs {
    water: AlignedRows<[u32; W]>,
    params: Vec<ParamRow>,
    was_wet: Vec<bool>,
    v0: Vec<L3>,
    drip_lanes: Vec<u8>,
    scratch: Vec<BlockScratch>,
}

impl Bufs {
    fn take(h: &mut Held) -> Bufs {
        Bufs {
            water: std::mem::take(&mut h.water),
            params: std::mem::take(&mut h.params),
            was_wet: std::mem::take(&mut h.params_wet),
            v0: std::mem::take(&mut h.v0),
            drip_lanes: std::mem::take(&mut h.drip_lanes),
            scratch: std::mem::take(&mut h.tasks),
        }
    }

    fn put(self, h: &mut Held) {
        (h.water, h.params, h.params_wet, h.v0) = (self.water, self.params, self.was_wet, self.v0);
        (h.drip_lanes, h.tasks) = (self.drip_lanes, self.scratch);
    }
}

/// What finishing a block reads: the laws' inputs and the rows' constants.
struct Finish<'a> {
    src: ParamSource<'a>,
    state: &'a [StateRow],
    /// `None` when water does not dry.
    dry: Option<DryLaw>,
    free: Option<&'a [u8]>,
    /// Whether the laws run compiled for AVX2.
    avx2: bool,
}

impl<'a> Finish<'a> {
    /// `dry`, the saturation, the next step's parameters and bridge marks of the block whose
    /// first row is `r0`. Returns the quanta evaporated and whether any point holds water.
    #[inline(always)]
    fn block(&self, r0: usize, out: Rows, scratch: &mut BlockScratch) -> (u64, bool) {
        let n = out.water.len();
        let (cap, hold) = (&self.src.capacity[r0..r0 + n], &self.src.hold[r0..r0 + n]);
        // Each law compiled on its own (for AVX2 where the CPU has it): inlined into one
        // body, the compiler left the drying's lanes partly scalar.
        let lost = match self.dry {
            Some(law) => avx2(
                self.avx2,
                #[inline(always)]
                || held_rows::dry_rows(out.water, &self.state[r0..], law),
            ),
            None => 0,
        };
        let sat = &mut scratch.sat;
        let any = avx2(
            self.avx2,
            #[inline(always)]
            || held_rows::saturation_rows(out.water, cap, hold, out.wetness, Some(&mut *sat)),
        );
        avx2(
            self.avx2,
            #[inline(always)]
            || held_rows::refresh_rows(&self.src, r0, out.water, |k| sat[k], out.params, out.was_wet),
        );
        if let Some(free) = self.free {
            avx2(
                self.avx2,
                #[inline(always)]
                || held_rows::bridge_marks(out.water, cap, &free[r0..r0 + n], out.marks),
            );
        }
        // The block's flow and drips are done with this step's: keep the next step's.
        for (v0, s) in out.v0.iter_mut().zip(&self.state[r0..r0 + n]) {
            *v0 = s.v;
        }
        (lost, any)
    }
    /// The laws' inputs for this step (`free`: with bridges, each row's free lanes).
    fn new(
        held: &'a Held,
        lay: &'a Layout,
        state: &'a [StateRow],
        wind: Vec3,
        dt: f32,
        free: Option<&'a [u8]>,
    ) -> Self {
        let cfg = held.cfg;
        Finish {
            src: held.param_source(lay),
            state,
            dry: (cfg.dry_time > 0.0).then_some(DryLaw {
                wind,
                tau: cfg.dry_time,
                u_ref: cfg.dry_air_speed,
                dt,
            }),
            free,
            avx2: held.avx2,
        }
    }
}

impl Held {
    /// The passes after the substeps (see the module's note): `flow`, `drip` (with `drops`:
    /// the scene drips), `dry`, the saturation into `out.wetness`, and the next step's
    /// parameters and bridge marks, which [`Held::take_fresh`] then reports as done. Does
    /// nothing while no point may hold water (the wetness is then already zero).
    #[allow(clippy::too_many_arguments)]
    pub fn settle(
        &mut self,
        lay: &Layout,
        state: &[StateRow],
        g: Vec3,
        dt: f32,
        wind: Vec3,
        drops: Option<DropSink>,
        out: SettleOut,
        pool: Option<&Pool>,
        clock: &mut StageClock,
    ) {
        self.fresh = false;
        let t = clock.start();
        if !self.may_hold {
            clock.stop(Stage::Flow, t);
            if drops.is_some() {
                clock.stop(Stage::Drip, clock.start());
            }
            clock.stop(Stage::Dry, clock.start());
            return;
        }
        let (rows, per_task) = (lay.rows, super::held::BLOCKS_PER_TASK);
        let min_drop = wet::to_quanta(self.cfg.drip_mass as f64).max(1);
        let drips = drops.is_some();
        let (free, marks) = match out.bridges {
            Some((free, marks)) => (Some(free), marks),
            None => (None, &mut [][..]),
        };
        let wetness = out.wetness;
        let (av, speed, flows) = (self.avx2, self.cfg.flow_speed(), !self.v0.is_empty());
        // The per-row buffers the pass writes, out of `self` while the laws read its
        // constants.
        let mut bufs = Bufs::take(self);
        let (lost, any) = {
            let finish = &Finish::new(self, lay, state, wind, dt, free);
            // One task per run of blocks: each block flows, then is finished unless it sheds
            // a drop. Returns the quanta evaporated and whether any point holds water.
            let task = |b0: usize, mut run: Rows, lanes: &mut [u8], t: &mut BlockScratch| -> (u64, bool) {
                let (mut lost, mut any) = (0u64, false);
                for j in 0..run.water.len() / rows {
                    let (b, r0) = (b0 + j, (b0 + j) * rows);
                    let block = run.block(j, rows);
                    if flows {
                        let st = &state[r0..];
                        avx2(
                            av,
                            #[inline(always)]
                            || {
                                held_rows::flow_block(
                                    lay,
                                    b,
                                    block.water,
                                    &finish.src.hold[r0..],
                                    st,
                                    block.v0,
                                    g,
                                    speed,
                                    dt,
                                )
                            },
                        );
                    }
                    if drips {
                        let hold = &finish.src.hold[r0..r0 + rows];
                        lanes[j] = avx2(
                            av,
                            #[inline(always)]
                            || held_rows::drip_lanes(block.water, hold, min_drop),
                        );
                        if lanes[j] != 0 {
                            continue; // finished after the drip pass
                        }
                    }
                    let (l, a) = finish.block(r0, block, t);
                    lost += l;
                    any |= a;
                }
                (lost, any)
            };
            let tasks = bufs.water.len().div_ceil(rows * per_task);
            let size = rows * per_task;
            let task = &task;
            let b = &mut bufs;
            let (wetness, marks) = (&mut *wetness, &mut *marks);
            let mut body = move || {
                b.water
                    .par_chunks_mut(size)
                    .zip(b.params.par_chunks_mut(size))
                    .zip(b.was_wet.par_chunks_mut(size))
                    .zip(wetness.par_chunks_mut(size))
                    .zip(chunks_or_empty(marks, size, tasks))
                    .zip(chunks_or_empty(&mut b.v0, size, tasks))
                    .zip(chunks_or_empty(&mut b.drip_lanes, per_task, tasks))
                    .zip(b.scratch.par_iter_mut())
                    .enumerate()
                    .map(
                        |(c, (((((((water, params), was_wet), wetness), marks), v0), lanes), t))| {
                            let run = Rows {
                                water,
                                params,
                                was_wet,
                                wetness,
                                marks,
                                v0,
                            };
                            task(c * per_task, run, lanes, t)
                        },
                    )
                    .reduce(|| (0, false), |a, b| (a.0 + b.0, a.1 | b.1))
            };
            match pool {
                Some(pool) => pool.install(body),
                None => body(),
            }
        };
        bufs.put(self);
        self.evaporated += lost;
        self.may_hold = any;
        clock.stop(Stage::Flow, t);
        if let Some(sink) = drops {
            let t = clock.start();
            self.drip(lay, state, g, dt, min_drop, sink);
            clock.stop(Stage::Drip, t);
            // The blocks that shed drops, finished now that their drops have left.
            let t = clock.start();
            let mut bufs = Bufs::take(self);
            let finish = Finish::new(self, lay, state, wind, dt, free);
            let (mut lost, mut any) = (0u64, false);
            let scratch = &mut bufs.scratch[0];
            let mut all = Rows {
                water: &mut bufs.water,
                params: &mut bufs.params,
                was_wet: &mut bufs.was_wet,
                wetness,
                marks,
                v0: &mut bufs.v0,
            };
            for (b, _) in bufs.drip_lanes.iter().enumerate().filter(|(_, &m)| m != 0) {
                let (l, a) = finish.block(b * rows, all.block(b, rows), scratch);
                lost += l;
                any |= a;
            }
            bufs.put(self);
            self.evaporated += lost;
            self.may_hold |= any;
            clock.stop(Stage::Dry, t);
        } else {
            clock.stop(Stage::Dry, clock.start());
        }
        self.params_wet_any = self.may_hold;
        self.fresh = true;
    }

    /// Pass `drip` (§6): a point holding more than its hold limit by at least the drip mass
    /// `min_drop`, and from which the water cannot run on along the strand (no neighbour lies
    /// along its effective gravity: a hanging strand's tip, the bottom of a loop, any point
    /// when water does not flow), sheds the excess as a new particle with the point's
    /// velocity, `reach` below it along its effective gravity (where the drop hung as it let
    /// go: just out of the pull of the point it left), strand by strand in the host's order
    /// (so the drops are numbered alike on every run). When the particles are full the
    /// excess waits. Visits only the lanes marked in `drip_lanes` (most strands have none:
    /// visiting every point in the host's order, a cache miss per strand, was most of the
    /// pass).
    fn drip(&mut self, lay: &Layout, state: &[StateRow], g: Vec3, dt: f32, min_drop: u32, sink: DropSink) {
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            if self.drip_lanes[b] & (1 << l) == 0 {
                continue;
            }
            let rows = b * lay.rows..b * lay.rows + lay.strand_points(s);
            for r in rows.clone() {
                let q = wet::drip(self.water[r][l], self.hold[r][l], min_drop);
                if q == 0 {
                    continue;
                }
                let g_eff = g_eff(&self.v0, state, r, l, g, dt);
                if !self.v0.is_empty() && runs_on(state, &rows, r, l, g_eff) {
                    continue;
                }
                let x = state[r].x.get(l) + sink.reach * g_eff.normalize_or_zero();
                if sink.water.add_drop(x, state[r].v.get(l), q, sink.capacity) {
                    self.water[r][l] -= q;
                }
            }
        }
    }
}

/// Gravity less the acceleration over the step of lane `l` of row `r` (gravity alone when
/// water does not flow and no velocities were kept).
fn g_eff(v0: &[L3], state: &[StateRow], r: usize, l: usize, g: Vec3, dt: f32) -> Vec3 {
    match v0.get(r) {
        Some(v0) => g - (state[r].v.get(l) - v0.get(l)) / dt,
        None => g,
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
    use crate::params::{HeldWater, SimParams};

    /// What the pass leaves for the next step is what the sweeps at the step's start would
    /// compute from the water it leaves: the parameters (bit for bit), the velocities and
    /// the bridge marks; and `take_fresh` answers once.
    #[test]
    fn the_pass_leaves_what_the_next_step_would_compute() {
        let groom = crate::groom::paper_scene(300, 6).unwrap();
        let params = SimParams {
            held_water: HeldWater::ON,
            ..SimParams::paper()
        };
        let lay = Layout::new(&groom, &params);
        let mut state = lay.rest_state(&glam::Affine3A::IDENTITY);
        let mut held = Held::new(&lay, params.held_water);
        held.soak(0.6);
        // Uneven water: some rows dry, some over the hold limit.
        for (k, w) in held.water.iter_mut().enumerate() {
            for l in 0..W {
                w[l] = match (k + l) % 5 {
                    0 => 0,
                    1 => held.hold[k][l] * 2,
                    _ => w[l],
                };
            }
        }
        held.keep_velocities(&state, None);
        // The step moved the points: flow reads the kept velocities, the next step the new.
        for (k, r) in state.iter_mut().enumerate() {
            for l in 0..W {
                r.v.x[l] = 0.01 * ((k * W + l) % 7) as f32;
            }
        }
        let mut wetness = vec![[0.0; W]; state.len()];
        let free = vec![0xff; state.len()];
        let mut marks = vec![0; state.len()];
        let out = SettleOut {
            wetness: &mut wetness,
            bridges: Some((&free, &mut marks)),
        };
        let g = params.gravity;
        held.settle(
            &lay,
            &state,
            g,
            1.0 / 60.0,
            Vec3::ZERO,
            None,
            out,
            None,
            &mut StageClock::default(),
        );
        assert!(held.may_hold());
        let mut fresh = Held::new(&lay, params.held_water);
        fresh.water = held.water.clone();
        fresh.may_absorb();
        fresh.refresh_params(&lay, None);
        assert_eq!(format!("{:?}", held.params), format!("{:?}", fresh.params));
        let mut want = vec![0; state.len()];
        held_rows::bridge_marks(&held.water, &held.capacity, &free, &mut want);
        assert_eq!(marks, want);
        assert!(marks.iter().any(|&m| m != 0) && marks.iter().any(|&m| m != 0xff));
        assert!(held
            .v0
            .iter()
            .zip(&state)
            .all(|(v0, s)| format!("{v0:?}") == format!("{:?}", s.v)));
        assert!(held.take_fresh() && !held.take_fresh());
        held.soak(1.0);
        assert!(!held.take_fresh(), "the host changed the water");
    }
}
