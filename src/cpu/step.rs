//! The CPU step's scheduling: the plan's passes run over strand blocks on the simulation's
//! worker pool (the block kernel is `kernel.rs`).
//!
//! Without water nothing couples one block to another, so each worker runs *all* substeps of a
//! block while it sits in cache ("fused" order). With water, particles couple blocks, so every
//! substep visits all blocks before the particles move. Both orders run the same block kernel.

use super::aligned_rows::AlignedRows;
use super::avx2::cpu_has_avx2;
use super::kernel::{block_substep, AbsorbCtx, Ctx, WaterCtx, Worker};
use super::layout::{Layout, StateRow};
use super::pool::chunks_or_empty;
use super::settle::{DropSink, SettleOut};
use super::slot_spans::SlotSpan;
use super::water::Water;
use crate::error::{Error, Result};
use crate::params::{Integrator, SimParams};
use crate::physics::bdf2::{Bdf2Blend, Bdf2Clock, Bdf2Row};
use crate::physics::collide::{ColliderFrames, Colliders, Placed};
use crate::physics::head::head_between;
use crate::physics::integrate::blown_up;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::roots::RootFrame;
use crate::physics::sdf::PlacedSdf;
use crate::physics::spring::DampingModel;
use crate::plan::{has_bend, pass_list, resolve_integrator, Pass, WaterDomain};
use crate::timers::{Stage, StageClock};
use glam::{Affine3A, Vec3};
use rayon::prelude::*;

/// What one step measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepReport {
    /// Largest point speed seen, m/s.
    pub max_speed: f32,
    /// Particles removed at the end of the step.
    pub water_removed: usize,
}

/// The CPU backend's state.
#[derive(Debug)]
pub struct CpuBackend {
    /// Layout and constant per-row data.
    pub lay: Layout,
    /// Positions and velocities, per row.
    pub state: Vec<StateRow>,
    /// Wetness per row (empty until water is first added).
    pub wet: AlignedRows<Lane>,
    /// Water particles (None until first added).
    pub water: Option<Water>,
    /// Water held by the hair (None unless the scene has it).
    pub held: Option<super::held::Held>,
    /// Liquid bridges between wet strands (None unless the scene has them).
    pub(super) bridges: Option<super::bridges::Bridges>,
    /// The wind this step, m/s.
    wind: Vec3,
    params: SimParams,
    /// Worker threads.
    threads: usize,
    /// Scratch per chunk of blocks: the blocks are cut into [`CHUNKS_PER_THREAD`] chunks per
    /// thread, taken by whichever thread is free, each with its own lists, joined in block
    /// order.
    workers: Vec<Worker>,
    pub(super) pool: Option<super::pool::Pool>,
    heads: Vec<Affine3A>,
    /// The analytic colliders placed for each substep (`n_sub` × colliders), from the head or
    /// from their own frames.
    placed: Vec<Placed>,
    /// The colliders' own frames over the next step (empty where they follow the head).
    pub(super) collider_frames: ColliderFrames,
    /// The SDF colliders' transforms at the start and end of the next step, and each
    /// substep's placement (`n_sub` × SDFs; empty without SDFs).
    sdf_from: Vec<Affine3A>,
    sdf_to: Vec<Affine3A>,
    placed_sdfs: Vec<PlacedSdf>,
    /// Skinned roots' frames (scenes with skinned roots only).
    roots: Option<super::roots::Roots>,
    /// Hair-hair volume's grid (scenes with it only).
    volume: Option<super::volume::Volume>,
    domain: WaterDomain,
    avx2: bool,
    integrator: Integrator,
    /// BDF2's history: each row's last displacement, velocities and rounding (BDF2 only).
    history: Vec<Bdf2Row>,
    /// BDF2's clock (which frames keep the history) and this frame's blends: the first
    /// substep's, then the others'.
    bdf2: (Bdf2Clock, (Bdf2Blend, Bdf2Blend)),
    /// Wall time per stage, when the host asks for it.
    pub(super) clock: StageClock,
    /// Positions per row where the output blend starts (fixed steps with interpolation; empty
    /// until first kept), and the blend (`None`: the output shows the state).
    pub(super) output_from: Vec<L3>,
    pub(super) output_blend: Option<f32>,
    /// Guides and followers' output (scenes with guides only).
    pub(super) followers: Option<super::followers::CpuFollowers>,
    /// Blocks the step runs (all but while a lower simulated fraction leaves guides out).
    pub(super) active_blocks: usize,
    /// The last step's adhesion pairs over its substeps (`Counters::adhesion_pairs`).
    pub(super) adhesion_pairs: u64,
    /// The largest share of eq. 2's pull times inverse mass of any hair point, dry (held
    /// water only makes points heavier): which rows may skip the stability limit's count
    /// (`physics/pull_limit.rs`).
    pull_weight_max: f32,
    /// Per row, how many strands' hair each point stands for (a guide groom's bundles,
    /// `physics/bundles.rs`; empty without guides, where it is 1): a guide asks a drop for
    /// its bundle's water and pulls it with its bundle's hair.
    pub(super) bundle: Vec<Lane>,
}

/// Chunks of blocks per worker thread. With water the work is uneven (the rows near
/// particles cost several times the others), so with one chunk per thread one thread waited
/// on the other; chunks taken as threads come free even it out (the paper scene with 1,000
/// particles on 2 threads: 3.97 → 3.56 ms a frame). Results do not depend on it: each chunk
/// keeps its own lists, joined in block order.
const CHUNKS_PER_THREAD: usize = 8;

impl CpuBackend {
    /// Lays out the groom, starts the worker pool, and allocates every step buffer.
    pub fn new(groom: &crate::groom::Groom, params: &SimParams, head: &Affine3A) -> Result<Self> {
        let lay = Layout::new(groom, params);
        let state = lay.rest_state(head);
        let threads = match params.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n as usize,
        }
        .min(lay.blocks.max(1));
        let pool = if threads > 1 {
            Some(super::pool::Pool::new(threads)?)
        } else {
            None
        };
        let integrator = resolve_integrator(params, groom);
        let chunks = if threads > 1 { threads * CHUNKS_PER_THREAD } else { 1 };
        let workers = (0..chunks.min(lay.blocks.max(1)))
            .map(|_| {
                let mut w = Worker {
                    f: vec![L3::ZERO; lay.rows],
                    ..Default::default()
                };
                w.scratch_for(integrator, lay.rows);
                w
            })
            .collect();
        let n_sub = params.substeps as usize;
        let hw = params.held_water;
        hw.check_masses(&lay.mass)?;
        let held = hw.enabled.then(|| super::held::Held::new(&lay, hw));
        let bridges = hw
            .bridges()
            .then(|| super::bridges::Bridges::new(&lay, hw.bridge_tension, hw.bridge_length_for(&params.water)));
        // With held water, the wetness attribute is the saturation from the start.
        let wet = if held.is_some() {
            AlignedRows::filled([0.0; W], state.len())
        } else {
            AlignedRows::default()
        };
        let history = if integrator == Integrator::BDF2 {
            vec![Bdf2Row::default(); state.len()]
        } else {
            Vec::new()
        };
        let mut cpu = CpuBackend {
            lay,
            state,
            wet,
            water: None,
            held,
            bridges,
            wind: params.wind.velocity,
            params: params.clone(),
            threads,
            workers,
            pool,
            heads: vec![*head; n_sub],
            placed: vec![Placed::default(); n_sub * params.colliders.len()],
            collider_frames: ColliderFrames::new(&params.collider_frames),
            sdf_from: params.sdfs.iter().map(|s| s.transform).collect(),
            sdf_to: params.sdfs.iter().map(|s| s.transform).collect(),
            placed_sdfs: Vec::new(),
            roots: None,
            volume: None,
            domain: WaterDomain::new(groom, params),
            avx2: cpu_has_avx2(),
            integrator,
            history,
            bdf2: (Bdf2Clock::default(), (Bdf2Blend::euler(0.0), Bdf2Blend::euler(0.0))),
            clock: StageClock::default(),
            output_from: Vec::new(),
            output_blend: None,
            followers: None,
            active_blocks: 0,
            adhesion_pairs: 0,
            pull_weight_max: crate::plan::water::pull_weight_max(params, groom),
            bundle: Vec::new(),
        };
        cpu.active_blocks = cpu.lay.blocks;
        if params.skinned_roots {
            cpu.roots = Some(super::roots::Roots::new(&cpu.lay));
        }
        if params.volume.enabled {
            cpu.volume = Some(super::volume::Volume::new(groom, &params.volume, cpu.threads)?);
        }
        if hw.drips() {
            // Drops are made in the step, which never allocates: their storage comes now.
            cpu.allocate_water();
        }
        Ok(cpu)
    }

    /// The parameters the backend was made with.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// The integrator in use (`Auto` resolved).
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Worker threads in use.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// The passes the next step will run, in order (once per step before the substeps, per
    /// substep, then once per step).
    pub fn passes(&self) -> Vec<Pass> {
        let wet = self.water.as_ref().is_some_and(|w| !w.is_empty());
        let p = &self.params;
        pass_list(p, self.integrator, has_bend(p, self.lay.rows), wet)
    }

    /// Every buffer the backend holds, with its size in bytes (capacity, not length): what a
    /// scene costs in memory, and proof that unused features allocate nothing.
    pub fn buffers(&self) -> Vec<(&'static str, usize)> {
        fn bytes<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let mut out = vec![
            ("state", bytes(&self.state)),
            ("row_params", bytes(&self.lay.params)),
            ("rest_local", bytes(&self.lay.rest_local)),
            ("worker_forces", self.workers.iter().map(|w| bytes(&w.f)).sum()),
        ];
        if !self.wet.is_empty() {
            out.push(("wetness", self.wet.capacity() * std::mem::size_of::<Lane>()));
        }
        if let Some(f) = &self.followers {
            let d = &f.data;
            out.push((
                "followers",
                bytes(&d.strand_first) + bytes(&d.rest) + bytes(&d.spans) + bytes(&d.follow) + bytes(&d.from),
            ));
        }
        if !self.output_from.is_empty() {
            out.push(("output_from", bytes(&self.output_from)));
        }
        if !self.bundle.is_empty() {
            out.push(("bundles", bytes(&self.bundle)));
        }
        if let Some(h) = &self.held {
            out.push(("held_water", h.bytes()));
        }
        if let Some(b) = &self.bridges {
            out.push(("bridges", b.bytes()));
        }
        if let Some(w) = &self.water {
            let moved = bytes(&w.moved.0) + bytes(&w.moved.1) + bytes(&w.moved.2);
            out.push((
                "water_particles",
                bytes(&w.pos) + bytes(&w.vel) + bytes(&w.mass) + moved,
            ));
            out.push(("water_grid", w.grid.bytes() + w.sorted.iter().map(bytes).sum::<usize>()));
            out.push((
                "water_reactions",
                self.workers
                    .iter()
                    .map(|k| bytes(&k.reactions) + bytes(&k.spans))
                    .sum::<usize>()
                    + bytes(&w.force),
            ));
            if w.piles_bytes() > 0 {
                out.push(("water_piles", w.piles_bytes()));
            }
        }
        out
    }

    /// Adds particles, allocating water storage at the first call. With held water each
    /// carries `particle_mass` of water, booked as added.
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        let cap = self.params.water.capacity as usize;
        if self.water.is_none() && pos.len() > cap {
            return Err(Error::Capacity(format!(
                "{} particles exceed the water capacity {cap}",
                pos.len()
            )));
        }
        self.allocate_water();
        let quanta = crate::physics::wet::to_quanta(self.params.water.particle_mass as f64);
        self.water.as_mut().expect("allocated above").add(pos, vel, cap, quanta)
    }

    /// Particle storage and the per-worker lists that go with it, made once: at the first
    /// add, or at create when held water can drip.
    fn allocate_water(&mut self) {
        if self.water.is_some() {
            return;
        }
        let cap = self.params.water.capacity as usize;
        let hw = &self.params.held_water;
        self.water = Some(Water::new(
            &self.params.water,
            self.domain,
            hw.enabled,
            self.params.coalesces(),
        ));
        if self.wet.is_empty() {
            self.wet = AlignedRows::filled([0.0; W], self.state.len());
        }
        // A chunk holds at most this many blocks (`run_blocks`), each one span.
        let per_chunk = self.lay.blocks.div_ceil(self.workers.len()).max(1);
        for w in &mut self.workers {
            w.reactions = Vec::with_capacity(cap);
            w.spans = Vec::with_capacity(per_chunk);
            if hw.absorbs() {
                w.demands = Vec::with_capacity(cap);
                w.demand_spans = Vec::with_capacity(per_chunk);
            }
        }
    }

    /// Removes all water (wetness stays).
    pub fn clear_water(&mut self) {
        if let Some(w) = &mut self.water {
            w.clear();
        }
    }

    /// Back to the rest pose at `head`: zero velocity, dry, no water.
    pub fn reset(&mut self, head: &Affine3A) {
        self.state = self.lay.rest_state(head);
        self.output_blend = None;
        self.bdf2.0 = Bdf2Clock::default();
        self.adhesion_pairs = 0;
        self.wet.iter_mut().for_each(|w| *w = [0.0; W]);
        if let Some(h) = &mut self.held {
            h.reset(&self.lay);
        }
        if let Some(b) = &mut self.bridges {
            b.reset();
        }
        if let Some(w) = &mut self.water {
            w.reset();
        }
    }

    /// The position of host point `i`.
    pub fn position_of(&self, i: usize) -> Vec3 {
        let f = &self.lay.strand_first;
        let s = f.partition_point(|&a| a as usize <= i) - 1;
        let (b, l) = self.lay.lane_of(s);
        self.state[b * self.lay.rows + i - f[s] as usize].x.get(l)
    }

    /// Runs `n` substeps per step from the next step on (allocates only when `n` grows).
    pub fn set_substeps(&mut self, n: u32) {
        let n_sub = n as usize;
        self.params.substeps = n;
        self.heads.resize(n_sub, Affine3A::IDENTITY);
        self.placed
            .resize(n_sub * self.params.colliders.len(), Placed::default());
    }

    /// Runs `integrator` from the next step on, from the current state: gives the workers its
    /// scratch and BDF2 its history, and starts BDF2 again from a backward Euler step.
    pub fn set_integrator(&mut self, integrator: Integrator) {
        for w in &mut self.workers {
            w.scratch_for(integrator, self.lay.rows);
        }
        if integrator == Integrator::BDF2 && self.history.is_empty() {
            self.history = vec![Bdf2Row::default(); self.state.len()];
        }
        self.bdf2.0 = Bdf2Clock::default();
        self.integrator = integrator;
    }

    /// Sets the wind of the next step.
    pub fn set_wind(&mut self, wind: Vec3) {
        self.wind = wind;
    }

    /// Where the water went (held water only).
    pub fn ledger(&self) -> Option<crate::engine::WaterLedger> {
        let mut l = self.held.as_ref()?.ledger();
        if let Some(w) = &self.water {
            l.added += w.added;
            l.in_particles = w.water_quanta();
            l.left = w.left;
        }
        Some(l)
    }

    /// Advances by `dt` seconds in `substeps` substeps while the head moves from `from` to `to`.
    pub fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<StepReport> {
        let _ftz = super::denormals::FlushDenormals::new();
        let n_sub = self.params.substeps as usize;
        let h = dt / n_sub as f32;
        if self.integrator == Integrator::BDF2 {
            self.bdf2.1 = self.bdf2.0.frame(h, n_sub as u32);
        }
        let nc = self.params.colliders.len();
        crate::physics::head::substep_heads_into(from, to, &mut self.heads);
        let inv_h = 1.0 / h;
        self.collider_frames
            .place_substeps(&self.params.colliders, from, &self.heads, inv_h, &mut self.placed);
        self.placed_sdfs.clear();
        for s in 0..n_sub {
            for (k, sdf) in self.params.sdfs.iter().enumerate() {
                let path = |a: usize| head_between(&self.sdf_from[k], &self.sdf_to[k], a as f32 / n_sub as f32);
                self.placed_sdfs
                    .push(PlacedSdf::moving(sdf, &path(s), &path(s + 1), inv_h));
            }
        }
        for w in &mut self.workers {
            w.max_v2 = 0.0;
            w.nonfinite = false;
        }
        let wet = self.water.as_ref().is_some_and(|w| !w.is_empty());
        let axial = self.params.damping_model == DampingModel::AXIAL;
        let clock = &mut self.clock;
        if let Some(held) = &mut self.held {
            let t = clock.start();
            let held_at_start = held.may_hold();
            // wet_params: masses and limpness from the water, and the velocities flow reads,
            // unless the last step's pass after the substeps left them (with the bridges'
            // marks) for the water and state as they are.
            let fresh = held.take_fresh();
            if !fresh {
                held.refresh_params(&self.lay, self.pool.as_ref());
            }
            if wet {
                held.may_absorb();
            }
            if !fresh {
                held.keep_velocities(&self.state, self.pool.as_ref());
            }
            clock.stop(Stage::WetParams, t);
            if let Some(br) = &mut self.bridges {
                let t = clock.start();
                br.find_pairs(
                    &self.lay,
                    &self.state,
                    &held.water,
                    &held.capacity,
                    held.row_params(),
                    h,
                    held_at_start,
                    fresh,
                    self.pool.as_ref(),
                );
                clock.stop(Stage::HairGrid, t); // pass hair_grid
            }
        }
        if let Some(vol) = &mut self.volume {
            let t = self.clock.start();
            let chunk_rows = self.lay.blocks.div_ceil(self.threads).max(1) * self.lay.rows;
            let rows = self.held.as_ref().map_or(&self.lay.params[..], |h| h.row_params());
            vol.run(
                &mut self.state,
                rows,
                &self.wet,
                chunk_rows,
                from,
                dt,
                self.pool.as_ref(),
            ); // pass volume
            self.clock.stop(Stage::Volume, t);
        }
        let bridging = self.bridges.as_ref().is_some_and(|b| b.active());
        // BDF2 takes the explicit forces at x + h v (physics/bdf2.rs `explicit_lead`).
        let ahead = crate::physics::bdf2::explicit_lead(self.integrator, h);
        let mut report = StepReport::default();
        self.adhesion_pairs = 0;
        if wet || bridging {
            for s in 0..n_sub {
                if wet {
                    let t = self.clock.start();
                    let water = self.water.as_mut().expect("wet");
                    if s == 0 {
                        water.group_piles();
                    }
                    water.grid_build(self.pool.as_ref()); // pass water_grid
                    self.clock.stop(Stage::WaterGrid, t);
                }
                if bridging && s == 0 {
                    let t = self.clock.start();
                    let pool = self.pool.as_ref();
                    self.bridges.as_mut().expect("bridging").pack(&self.state, ahead, pool);
                    self.clock.stop(Stage::Cohesion, t); // pass cohesion (the blocks pull)
                }
                let t = self.clock.start();
                self.run_blocks(s..s + 1, h, wet, bridging, axial);
                self.clock.stop(Stage::Blocks, t);
                if bridging {
                    self.bridges.as_mut().expect("bridging").next_substep();
                }
                if !wet {
                    continue;
                }
                // Each pair left one reaction: counting them reads each worker's list length.
                self.adhesion_pairs += self.workers.iter().map(|w| w.reactions.len() as u64).sum::<u64>();
                let chunk_rows = self.blocks_per_chunk() * self.lay.rows;
                let water = self.water.as_mut().expect("wet");
                if let (Some(held), true) = (&mut self.held, self.params.held_water.absorbs()) {
                    let t = self.clock.start();
                    let last = (crate::physics::wet::to_quanta(self.params.water.particle_mass as f64) as f64
                        * crate::physics::wet::ABSORB_LAST_FRACTION) as u32;
                    water.absorb(&mut self.workers, &mut held.water, chunk_rows, last, self.pool.as_ref());
                    self.clock.stop(Stage::Absorb, t); // pass absorb
                }
                let t = self.clock.start();
                // Workers hold contiguous block ranges in order, so their lists one after
                // another are every block's reactions in block order, whatever the thread count.
                let reactions = self.workers.iter().map(|w| (&w.reactions[..], &w.spans[..]));
                water.integrate(
                    reactions,
                    &self.params.water,
                    self.params.gravity,
                    self.wind,
                    h,
                    Colliders {
                        placed: placed_of(&self.placed, s, nc),
                        sdfs: &self.params.sdfs,
                        placed_sdfs: placed_of(&self.placed_sdfs, s, self.params.sdfs.len()),
                    },
                    self.params.friction,
                    self.pool.as_ref(),
                );
                self.clock.stop(Stage::WaterIntegrate, t);
            }
            if wet {
                let water = self.water.as_ref().expect("wet");
                if water.pos.iter().chain(&water.vel).any(|p| !p.is_finite()) {
                    return Err(Error::Unstable {
                        strand: None,
                        detail: "a water particle became non-finite".into(),
                    });
                }
            }
        } else {
            let t = self.clock.start();
            self.run_blocks(0..n_sub, h, false, false, axial);
            self.clock.stop(Stage::Blocks, t);
        }
        let clock = &mut self.clock;
        if let Some(held) = &mut self.held {
            // Passes flow, drip and dry, and the next step's wet_params, block by block
            // (cpu/settle.rs).
            let drops = self.params.held_water.drips().then(|| DropSink {
                water: self.water.as_mut().expect("allocated at create when water can drip"),
                reach: self.params.water.r_max,
                capacity: self.params.water.capacity as usize,
            });
            let out = SettleOut {
                wetness: &mut self.wet,
                bridges: self.bridges.as_mut().map(|b| b.marks()),
            };
            held.settle(
                &self.lay,
                &self.state,
                self.params.gravity,
                dt,
                self.wind,
                drops,
                out,
                self.pool.as_ref(),
                clock,
            );
        }
        if wet {
            let t = clock.start();
            report.water_removed = self.water.as_mut().expect("wet").cull(to); // pass water_cull
            clock.stop(Stage::WaterCull, t);
        }
        if self.workers.iter().any(|w| w.nonfinite) {
            let strand = self.first_nonfinite_strand();
            return Err(Error::Unstable {
                strand,
                detail: format!("after a step of {dt} s in {n_sub} substeps"),
            });
        }
        report.max_speed = self.workers.iter().map(|w| w.max_v2).fold(0.0, f32::max).sqrt();
        Ok(report)
    }

    /// Runs substeps `subs` over every block, split into one chunk per worker (`wet`: with
    /// the particles; `bridging`: with the liquid bridges' forces).
    fn run_blocks(&mut self, subs: std::ops::Range<usize>, h: f32, wet: bool, bridging: bool, axial: bool) {
        let p = &self.params;
        let water = if wet { self.water.as_ref() } else { None };
        let held = self.held.as_ref();
        let rows = self.lay.rows;
        let per_chunk = self.blocks_per_chunk();
        // The bridges' positions at the substep's start, and each chunk's run of where its
        // blocks write theirs for the next.
        let (cohesion, next) = match self.bridges.as_mut().filter(|_| bridging) {
            Some(b) => {
                let (c, n) = b.cohesion(per_chunk);
                (Some(c), n)
            }
            None => (None, Vec::new()),
        };
        let ctx = Ctx {
            integrator: self.integrator,
            solver_iterations: p.solver_iterations,
            bdf2: self.bdf2.1,
            lay: &self.lay,
            params: held.map_or(&self.lay.params[..], |h| h.row_params()),
            avx2: self.avx2,
            h,
            g: p.gravity.to_array(),
            drag: p.hair_drag(),
            wind: self.wind.to_array(),
            cohesion: cohesion.as_ref(),
            bend: has_bend(p, self.lay.rows),
            heads: &self.heads,
            placed: &self.placed,
            n_colliders: p.colliders.len(),
            sdfs: &p.sdfs,
            placed_sdfs: &self.placed_sdfs,
            roots: self.roots.as_ref(),
            friction: p.friction,
            water: water.map(|w| WaterCtx {
                grid: &w.grid,
                sorted: &w.sorted,
                r_min: p.water.r_min,
                r_max: p.water.r_max,
                s: w.strength(p.water.adhesion),
                share: p.adhesion_share(),
                limit: crate::physics::pull_limit::PullLimit::new(
                    h,
                    p.water.r_min,
                    p.water.r_max,
                    (!p.held_water.absorbs()).then(|| w.strength(p.water.adhesion).strongest()),
                    self.pull_weight_max,
                ),
                // With held water, wetness is the saturation (written after the step).
                wet_gain: if held.is_some() {
                    0.0
                } else {
                    (p.water.wetting_rate * h).min(1.0)
                },
                absorb: held.filter(|_| p.held_water.absorbs()).map(|hd| AbsorbCtx {
                    mass: &w.sorted_mass,
                    strength_per_quantum: p.water.adhesion as f64
                        / (p.water.particle_mass as f64 / crate::physics::wet::WATER_QUANTUM),
                    take: crate::physics::wet::absorb_take(p.held_water.absorb_rate, h),
                    held: &hd.water,
                    hold: &hd.hold,
                }),
                bundle: &self.bundle,
            }),
        };
        let lock_step = subs.len() == 1;
        let run = |k: usize,
                   state: &mut [StateRow],
                   wet: &mut [Lane],
                   history: &mut [Bdf2Row],
                   worker: &mut Worker,
                   next: &mut [Vec3]| {
            worker.clear_lists();
            let first = k * per_chunk;
            let (blocks, at) = (state.len() / rows, state.as_ptr());
            for (j, rows_b) in state.chunks_mut(rows).enumerate() {
                // In lock step every block's rows have left the cache since its last substep:
                // the next block's are asked for now, while this one runs.
                if lock_step && j + 1 < blocks {
                    super::prefetch::next_block(&ctx, first + j + 1, at.wrapping_add((j + 1) * rows), rows);
                }
                let wet_b = if wet.is_empty() {
                    &mut [][..]
                } else {
                    &mut wet[j * rows..(j + 1) * rows]
                };
                let hist_b = if history.is_empty() {
                    &mut [][..]
                } else {
                    &mut history[j * rows..(j + 1) * rows]
                };
                let (start, asked) = (worker.reactions.len(), worker.demands.len());
                for s in subs.clone() {
                    if axial {
                        block_substep::<true>(&ctx, first + j, s, rows_b, wet_b, hist_b, worker);
                    } else {
                        block_substep::<false>(&ctx, first + j, s, rows_b, wet_b, hist_b, worker);
                    }
                }
                let (reactions, demands) = (&worker.reactions, &worker.demands);
                if let Some(span) = SlotSpan::of(reactions[start..].iter().map(|r| r.slot), reactions.len()) {
                    worker.spans.push(span);
                }
                if let Some(span) = SlotSpan::of(demands[asked..].iter().map(|d| d.slot), demands.len()) {
                    worker.demand_spans.push(span);
                }
                // The bridges' positions for the next substep (bridges run in lock step: one
                // substep here); this chunk's run of them starts at its first block's.
                if let Some(c) = ctx.cohesion {
                    c.write_next(first + j, rows_b, (first + j) * rows, c.first_of(first), next);
                }
            }
        };
        let chunk_rows = per_chunk * rows;
        // A lower simulated fraction leaves the last guides' blocks out.
        let active = self.active_blocks * rows;
        let (n_state, n_wet, n_hist) = (
            self.state.len().min(active),
            self.wet.len().min(active),
            self.history.len().min(active),
        );
        let (state, wet_rows, history, workers) = (
            &mut self.state[..n_state],
            &mut self.wet[..n_wet],
            &mut self.history[..n_hist],
            &mut self.workers,
        );
        // Workers past the last chunk run nothing this substep (a lower simulated fraction
        // left fewer blocks than workers): the lists they filled at an earlier substep must not
        // be read as this one's reactions and demands.
        let n = state.len().div_ceil(chunk_rows);
        workers.iter_mut().skip(n).for_each(Worker::clear_lists);
        let body = || {
            state
                .par_chunks_mut(chunk_rows)
                .zip(chunks_or_empty(wet_rows, chunk_rows, n))
                .zip(chunks_or_empty(history, chunk_rows, n))
                .zip(workers.par_iter_mut())
                .zip(parts_or_empty(next, n))
                .enumerate()
                .for_each(|(k, ((((s, wt), hs), w), x))| run(k, s, wt, hs, w, x));
        };
        match &self.pool {
            Some(pool) => pool.install(body),
            None => body(),
        }
    }

    /// Blocks in each worker's chunk (the last may hold fewer): the active blocks shared
    /// evenly, so that each chunk's lists name only its own blocks' points.
    fn blocks_per_chunk(&self) -> usize {
        self.active_blocks.div_ceil(self.workers.len()).max(1)
    }

    /// Host index of the first strand with a point that [`blown_up`] (the kernel's test), or
    /// `None` if none is.
    fn first_nonfinite_strand(&self) -> Option<u32> {
        (0..self.lay.strands).find_map(|s| {
            let (b, l) = self.lay.lane_of(s);
            let n = self.lay.strand_points(s);
            let rows = &self.state[b * self.lay.rows..b * self.lay.rows + n];
            rows.iter()
                .any(|r| blown_up(r.x.get(l), r.v.get(l)))
                .then_some(s as u32)
        })
    }

    /// Wets every point up to saturation `s` of its capacity (held water only).
    pub fn soak(&mut self, s: f32) -> Result<()> {
        let held = self.held.as_mut().ok_or_else(|| {
            Error::Unsupported("this simulation holds no water (SimParams::held_water is off)".into())
        })?;
        held.soak(s);
        held.saturation_into(&mut self.wet, self.pool.as_ref());
        Ok(())
    }

    /// Writes the host's attributes for every real point, strand after strand, into `dst`
    /// (exactly `points * stride` floats).
    pub fn write_vertices(&self, dst: &mut [f32]) {
        let attrs = self.params.attributes;
        let blend = self
            .output_blend
            .filter(|_| self.output_from.len() == self.state.len())
            .map(|a| (self.output_from.as_slice(), a));
        if let Some(f) = &self.followers {
            let guides = self.active_blocks * crate::physics::lanes::W;
            return f.write_vertices(
                &self.lay,
                &self.state,
                &self.wet,
                blend,
                guides,
                attrs,
                self.pool.as_ref(),
                dst,
            );
        }
        super::output::write_vertices(
            &self.lay,
            &self.state,
            &self.wet,
            blend,
            attrs,
            self.pool.as_ref(),
            self.avx2,
            dst,
        );
    }

    /// Moves the SDF colliders from `from` to `to` over the next step.
    pub fn place_sdfs(&mut self, from: &[Affine3A], to: &[Affine3A]) {
        self.sdf_from.clear();
        self.sdf_from.extend_from_slice(from);
        self.sdf_to.clear();
        self.sdf_to.extend_from_slice(to);
    }

    /// Moves the skinned roots from `from` to `to` (one per host strand) over the next step.
    pub fn place_roots(&mut self, from: &[RootFrame], to: &[RootFrame]) {
        if let Some(r) = &mut self.roots {
            r.place(&self.lay, from, to);
        }
    }

    /// Carries host strands `strands` rigidly from root frames `from` to `to` now, at rest,
    /// and starts BDF2 again (its history held the old place).
    pub fn carry_strands(&mut self, strands: &[u32], from: &[RootFrame], to: &[RootFrame]) {
        super::roots::Roots::carry(&self.lay, &mut self.state, strands, from, to);
        if let Some(h) = &mut self.held {
            h.state_changed();
        }
        self.restart_bdf2();
    }

    /// Starts BDF2 again from the current state (its history no longer matches it).
    pub(super) fn restart_bdf2(&mut self) {
        self.bdf2.0 = Bdf2Clock::default();
    }

    /// Keeps every row's positions as where the output blend starts (allocated on the first
    /// call only).
    pub fn keep_previous(&mut self) {
        self.output_from.clear();
        self.output_from.extend(self.state.iter().map(|r| r.x));
    }

    /// The output's blend from now on (see `Engine::blend_output`).
    pub fn blend_output(&mut self, a: Option<f32>) {
        self.output_blend = a;
    }
}

/// `parts` (one per chunk), or `n` empty slices when there are none (no bridges this substep).
fn parts_or_empty<T: Send>(parts: Vec<&mut [T]>, n: usize) -> impl IndexedParallelIterator<Item = &mut [T]> {
    if parts.is_empty() {
        rayon::iter::Either::Right((0..n).into_par_iter().map(|_| <&mut [T]>::default()))
    } else {
        rayon::iter::Either::Left(parts.into_par_iter())
    }
}

/// The colliders (or SDFs) placed for substep `s` (`nc` per substep).
fn placed_of<T>(placed: &[T], s: usize, nc: usize) -> &[T] {
    &placed[s * nc..(s + 1) * nc]
}
