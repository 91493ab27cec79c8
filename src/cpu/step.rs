//! The CPU step pipeline: one explicit list of passes, assembled from what the scene uses.
//!
//! Per substep, for every strand block: forces (drag, stretch, bend, adhesion) → integrate
//! (symplectic Euler; pinned points follow the head) → collide. Then, with water: the particles
//! integrate with the hair's reaction forces, and the grid is rebuilt for the next substep.
//!
//! Without water nothing couples one block to another, so each worker runs *all* substeps of a
//! block while it sits in cache ("fused" order). With water, particles couple blocks, so every
//! substep visits all blocks before the particles move. Both orders run the same block kernel.

use super::layout::{Layout, StateRow};
use super::water::Water;
use crate::error::{Error, Result};
use crate::params::Integrator;
use crate::params::{SimParams, VertexAttributes};
use crate::physics::adhesion;
use crate::physics::collide::{collide_row, Placed};
use crate::physics::implicit::{implicit_euler_block, BandScratch};
use crate::physics::integrate::symplectic_euler_row;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::spring::{spring, DampingModel};
use crate::physics::xpbd;
use glam::{Affine3A, Vec3};
use rayon::prelude::*;

/// Most grid columns one row query walks (a row spanning ~6 cells a side); wider rows query
/// lane by lane (3 x 3 columns each, as cells are r_max wide).
const MAX_RUNS: usize = 49;

/// One pass of the step, as reported by [`CpuBackend::passes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// Rebuild the water grid (counting sort).
    WaterGrid,
    /// Linear air drag on hair points.
    Drag,
    /// Stretch springs (i, i+1).
    StretchSprings,
    /// Bend springs (i, i+2).
    BendSprings,
    /// Eq. 2 between hair points and particles.
    Adhesion,
    /// Symplectic Euler (or XPBD's prediction); pinned points follow the head.
    Integrate,
    /// Implicit Euler: springs, Jacobians and each strand's banded solve, per Newton iteration.
    ImplicitSolve,
    /// XPBD: project stretch then bend constraints.
    ProjectConstraints,
    /// Push hair out of colliders.
    Collide,
    /// Integrate water particles (and collide them).
    WaterIntegrate,
    /// Remove particles that left the domain (once per step).
    WaterCull,
}

impl Pass {
    /// The pass's name, the same as the GPU entry point that mirrors it.
    pub fn name(self) -> &'static str {
        match self {
            Pass::WaterGrid => "water_grid",
            Pass::Drag => "drag",
            Pass::StretchSprings => "stretch_springs",
            Pass::BendSprings => "bend_springs",
            Pass::Adhesion => "adhesion",
            Pass::Integrate => "integrate",
            Pass::ImplicitSolve => "implicit_solve",
            Pass::ProjectConstraints => "project_constraints",
            Pass::Collide => "collide",
            Pass::WaterIntegrate => "water_integrate",
            Pass::WaterCull => "water_cull",
        }
    }
}

/// Per-worker scratch, allocated at create (water buffers at the first add).
#[derive(Debug, Default)]
pub struct Worker {
    f: Vec<L3>,
    /// Reaction forces on particles, in grid order, coordinates apart.
    water_force: [Vec<f32>; 3],
    max_v2: f32,
    nonfinite: bool,
    /// Banded system of one block (implicit Euler only).
    band: Option<BandScratch>,
    /// Positions before the substep (XPBD only).
    prev: Vec<L3>,
    /// Constraint multipliers, stretch then bend (XPBD only).
    lambda: Vec<Lane>,
}

/// What one step measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepReport {
    /// Largest point speed seen, m/s.
    pub max_speed: f32,
    /// Particles removed at the end of the step.
    pub water_removed: usize,
}

/// Constant inputs of one substep.
struct Ctx<'a> {
    integrator: Integrator,
    solver_iterations: u32,
    lay: &'a Layout,
    avx2: bool,
    h: f32,
    g: [f32; 3],
    drag: f32,
    bend: bool,
    heads: &'a [Affine3A],
    placed: &'a [Placed],
    n_colliders: usize,
    friction: f32,
    water: Option<WaterCtx<'a>>,
}

/// Water inputs of one substep (read-only while blocks run).
struct WaterCtx<'a> {
    grid: &'a crate::physics::grid::Grid,
    sorted: &'a [Vec<f32>; 3],
    r_min: f32,
    r_max: f32,
    s: f32,
    wet_gain: f32,
}

/// The CPU backend's state.
#[derive(Debug)]
pub struct CpuBackend {
    /// Layout and constant per-row data.
    pub lay: Layout,
    /// Positions and velocities, per row.
    pub state: Vec<StateRow>,
    /// Wetness per row (empty until water is first added).
    pub wet: Vec<Lane>,
    /// Water particles (None until first added).
    pub water: Option<Water>,
    params: SimParams,
    workers: Vec<Worker>,
    pool: Option<super::pool::Pool>,
    heads: Vec<Affine3A>,
    placed: Vec<Placed>,
    water_center: Vec3,
    water_radius: f32,
    avx2: bool,
    integrator: Integrator,
}

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
        let workers = (0..threads)
            .map(|_| Worker {
                f: vec![L3::ZERO; lay.rows],
                band: (integrator == Integrator::ImplicitEuler).then(|| BandScratch::new(lay.rows)),
                prev: if integrator == Integrator::Xpbd {
                    vec![L3::ZERO; lay.rows]
                } else {
                    Vec::new()
                },
                lambda: if integrator == Integrator::Xpbd {
                    vec![[0.0; W]; 2 * lay.rows]
                } else {
                    Vec::new()
                },
                ..Default::default()
            })
            .collect();
        let (lo, hi) = groom.bounds();
        let water_radius = if params.water.domain_radius > 0.0 {
            params.water.domain_radius
        } else {
            0.5 * (hi - lo).length() + groom.max_strand_length()
        };
        let n_sub = params.substeps as usize;
        Ok(CpuBackend {
            lay,
            state,
            wet: Vec::new(),
            water: None,
            params: params.clone(),
            workers,
            pool,
            heads: vec![*head; n_sub],
            placed: vec![Placed::default(); n_sub * params.colliders.len()],
            water_center: 0.5 * (lo + hi),
            water_radius,
            avx2: cpu_has_avx2(),
            integrator,
        })
    }

    /// The integrator in use (`Auto` resolved).
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Worker threads in use.
    pub fn threads(&self) -> usize {
        self.workers.len()
    }

    /// The passes the next step will run, in order (per substep, then once per step).
    pub fn passes(&self) -> Vec<Pass> {
        let wet = self.water.as_ref().is_some_and(|w| !w.is_empty());
        let p = &self.params;
        let bend = self.lay.rows > 2 && (p.bend.stiffness > 0.0 || p.bend.damping > 0.0);
        pass_list(p, self.integrator, bend, wet)
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
            out.push(("wetness", bytes(&self.wet)));
        }
        if let Some(w) = &self.water {
            out.push(("water_particles", bytes(&w.pos) + bytes(&w.vel)));
            out.push(("water_grid", w.grid.bytes() + w.sorted.iter().map(bytes).sum::<usize>()));
            out.push((
                "water_reactions",
                self.workers.iter().flat_map(|k| k.water_force.iter()).map(bytes).sum(),
            ));
        }
        out
    }

    /// Adds particles, allocating water storage at the first call.
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        let cap = self.params.water.capacity as usize;
        if self.water.is_none() {
            if pos.len() > cap {
                return Err(Error::Capacity(format!(
                    "{} particles exceed the water capacity {cap}",
                    pos.len()
                )));
            }
            self.water = Some(Water::new(&self.params.water, self.water_center, self.water_radius));
            self.wet = vec![[0.0; W]; self.state.len()];
            for w in &mut self.workers {
                w.water_force = [
                    Vec::with_capacity(cap),
                    Vec::with_capacity(cap),
                    Vec::with_capacity(cap),
                ];
            }
        }
        self.water.as_mut().expect("allocated above").add(pos, vel, cap)
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
        self.wet.iter_mut().for_each(|w| *w = [0.0; W]);
        if let Some(w) = &mut self.water {
            w.clear();
            w.removed = 0;
        }
    }

    /// Advances by `dt` seconds in `substeps` substeps while the head moves from `from` to `to`.
    pub fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<StepReport> {
        let _ftz = super::denormals::FlushDenormals::new();
        let n_sub = self.params.substeps as usize;
        let h = dt / n_sub as f32;
        let nc = self.params.colliders.len();
        crate::physics::head::substep_heads_into(from, to, &mut self.heads);
        for s in 0..n_sub {
            for (c, shape) in self.params.colliders.iter().enumerate() {
                self.placed[s * nc + c] = shape.place(&self.heads[s]);
            }
        }
        for w in &mut self.workers {
            w.max_v2 = 0.0;
            w.nonfinite = false;
        }
        let wet = self.water.as_ref().is_some_and(|w| !w.is_empty());
        let axial = self.params.damping_model == DampingModel::Axial;
        let mut report = StepReport::default();
        if wet {
            for s in 0..n_sub {
                self.water.as_mut().expect("wet").grid_build(); // pass water_grid
                self.run_blocks(s..s + 1, h, true, axial);
                let placed = &self.placed[s * nc..(s + 1) * nc];
                let water = self.water.as_mut().expect("wet");
                let forces = self.workers.iter().map(|w| &w.water_force);
                water.integrate(
                    forces,
                    &self.params.water,
                    self.params.gravity,
                    h,
                    placed,
                    self.params.friction,
                );
            }
            let water = self.water.as_mut().expect("wet");
            if water.pos.iter().chain(&water.vel).any(|p| !p.is_finite()) {
                return Err(Error::Unstable {
                    strand: u32::MAX,
                    detail: "a water particle became non-finite".into(),
                });
            }
            report.water_removed = water.cull(to);
        } else {
            self.run_blocks(0..n_sub, h, false, axial);
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

    /// Runs substeps `subs` over every block, split into one chunk per worker.
    fn run_blocks(&mut self, subs: std::ops::Range<usize>, h: f32, wet: bool, axial: bool) {
        let p = &self.params;
        let water = if wet { self.water.as_ref() } else { None };
        let ctx = Ctx {
            integrator: self.integrator,
            solver_iterations: p.solver_iterations,
            lay: &self.lay,
            avx2: self.avx2,
            h,
            g: p.gravity.to_array(),
            drag: p.air_drag,
            bend: self.lay.rows > 2 && (p.bend.stiffness > 0.0 || p.bend.damping > 0.0),
            heads: &self.heads,
            placed: &self.placed,
            n_colliders: p.colliders.len(),
            friction: p.friction,
            water: water.map(|w| WaterCtx {
                grid: &w.grid,
                sorted: &w.sorted,
                r_min: p.water.r_min,
                r_max: p.water.r_max,
                s: p.water.adhesion,
                wet_gain: (p.water.wetting_rate * h).min(1.0),
            }),
        };
        let n_particles = water.map_or(0, |w| w.len());
        let rows = self.lay.rows;
        let per_chunk = self.lay.blocks.div_ceil(self.workers.len()).max(1);
        let run = |k: usize, state: &mut [StateRow], wet: &mut [Lane], worker: &mut Worker| {
            if ctx.water.is_some() {
                for c in &mut worker.water_force {
                    c.clear();
                    c.resize(n_particles, 0.0);
                }
            }
            let first = k * per_chunk;
            for (j, rows_b) in state.chunks_mut(rows).enumerate() {
                let wet_b = if wet.is_empty() {
                    &mut [][..]
                } else {
                    &mut wet[j * rows..(j + 1) * rows]
                };
                for s in subs.clone() {
                    if axial {
                        block_substep::<true>(&ctx, first + j, s, rows_b, wet_b, worker);
                    } else {
                        block_substep::<false>(&ctx, first + j, s, rows_b, wet_b, worker);
                    }
                }
            }
        };
        let chunk_rows = per_chunk * rows;
        let (state, wet_rows, workers) = (&mut self.state, &mut self.wet, &mut self.workers);
        let mut body = || {
            if wet_rows.is_empty() {
                state
                    .par_chunks_mut(chunk_rows)
                    .zip(workers.par_iter_mut())
                    .enumerate()
                    .for_each(|(k, (s, w))| run(k, s, &mut [], w));
            } else {
                state
                    .par_chunks_mut(chunk_rows)
                    .zip(wet_rows.par_chunks_mut(chunk_rows))
                    .zip(workers.par_iter_mut())
                    .enumerate()
                    .for_each(|(k, ((s, wt), w))| run(k, s, wt, w));
            }
        };
        match &self.pool {
            Some(pool) => pool.install(body),
            None => body(),
        }
    }

    /// Host index of the first strand holding a non-finite position or velocity.
    fn first_nonfinite_strand(&self) -> u32 {
        for s in 0..self.lay.strands {
            let (b, l) = self.lay.lane_of(s);
            let n = self.lay.strand_points(s);
            for r in &self.state[b * self.lay.rows..b * self.lay.rows + n] {
                if !(r.x.get(l).is_finite() && r.v.get(l).is_finite()) {
                    return s as u32;
                }
            }
        }
        u32::MAX
    }

    /// Writes the host's attributes for every real point, strand after strand, into `dst`
    /// (exactly `points * stride` floats).
    pub fn write_vertices(&self, attrs: VertexAttributes, dst: &mut [f32]) {
        super::output::write_vertices(&self.lay, &self.state, &self.wet, attrs, self.pool.as_ref(), dst);
    }
}

/// One substep of one block, compiled for the best instruction set this CPU has (AVX2 where
/// present, else the baseline). No FMA contraction happens in either, so both give the same
/// bits.
#[inline(always)]
fn block_substep<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    worker: &mut Worker,
) {
    #[cfg(target_arch = "x86_64")]
    if ctx.avx2 {
        // SAFETY: `avx2` was set from `is_x86_feature_detected!("avx2")` at create.
        unsafe { block_substep_avx2::<AXIAL>(ctx, b, s, rows, wet, worker) };
        return;
    }
    block_substep_base::<AXIAL>(ctx, b, s, rows, wet, worker)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_substep_avx2<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    worker: &mut Worker,
) {
    block_substep_impl::<AXIAL>(ctx, b, s, rows, wet, worker)
}

#[inline(never)]
fn block_substep_base<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    worker: &mut Worker,
) {
    block_substep_impl::<AXIAL>(ctx, b, s, rows, wet, worker)
}

/// One substep of one block: forces → integrate → collide. The heart of the CPU backend.
#[inline(always)]
fn block_substep_impl<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    worker: &mut Worker,
) {
    let lay = ctx.lay;
    let p = lay.rows;
    let base = b * p;
    let params = &lay.params[base..base + p];
    let f = &mut worker.f[..p];

    // Pass: drag (or clear the force accumulators).
    for (fi, r) in f.iter_mut().zip(rows.iter()) {
        for l in 0..W {
            fi.x[l] = -ctx.drag * r.v.x[l];
            fi.y[l] = -ctx.drag * r.v.y[l];
            fi.z[l] = -ctx.drag * r.v.z[l];
        }
    }
    // Pass: stretch springs (i, i+1) (XPBD projects them as constraints instead).
    // (Implicit Euler evaluates them inside its Newton iterations.)
    let springs_as_forces = ctx.integrator == Integrator::SymplecticEuler;
    for i in (0..p - 1).filter(|_| springs_as_forces) {
        let (fa, fb) = f.split_at_mut(i + 1);
        let (ra, rb) = (&rows[i], &rows[i + 1]);
        spring::<AXIAL>(&ra.x, &rb.x, &ra.v, &rb.v, &params[i].stretch, &mut fa[i], &mut fb[0]);
    }
    // Pass: bend springs (i, i+2).
    if ctx.bend && springs_as_forces {
        for i in 0..p - 2 {
            let (fa, fb) = f.split_at_mut(i + 2);
            let (ra, rb) = (&rows[i], &rows[i + 2]);
            spring::<AXIAL>(&ra.x, &rb.x, &ra.v, &rb.v, &params[i].bend, &mut fa[i], &mut fb[0]);
        }
    }
    // Pass: adhesion (eq. 2), gathered per hair point; reactions go to this worker's
    // particle force buffer (summed over workers before the particles move).
    if let Some(w) = &ctx.water {
        for (i, r) in rows.iter().enumerate() {
            // Which lanes can have a particle within r_max (SIMD prefilter), minus padding.
            let mut lanes = w.grid.may_have_near_lanes(&r.x, w.r_max) & lay.real_lanes[base + i] as u32;
            if lanes == 0 {
                continue;
            }
            let [fx, fy, fz] = &mut worker.water_force;
            // Row path: one query for the lanes' bounds, each particle against all lanes at once.
            // Morton-ordered strands keep most rows compact; a row too wide for MAX_RUNS columns
            // goes lane by lane.
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            let mut mask = [0.0f32; W];
            for l in 0..W {
                if lanes & (1 << l) != 0 {
                    mask[l] = 1.0;
                    lo = lo.min(r.x.get(l));
                    hi = hi.max(r.x.get(l));
                }
            }
            let mut runs = [(0u32, 0u32); MAX_RUNS];
            let mut acc = L3::ZERO;
            let mut near = [0.0f32; W];
            if let Some(n) = w.grid.runs_in_box(lo - w.r_max, hi + w.r_max, &mut runs) {
                for &(s, e) in &runs[..n] {
                    let (s, e) = (s as usize, e as usize);
                    let run = adhesion::Run {
                        x: &w.sorted[0][s..e],
                        y: &w.sorted[1][s..e],
                        z: &w.sorted[2][s..e],
                    };
                    let (ox, oy, oz) = (&mut fx[s..e], &mut fy[s..e], &mut fz[s..e]);
                    adhesion::gather_run_lanes(
                        &r.x, &mask, run, ox, oy, oz, &mut acc, &mut near, w.r_min, w.r_max, w.s,
                    );
                }
            } else {
                while lanes != 0 {
                    let l = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    let mut one = [0.0f32; W];
                    one[l] = 1.0;
                    let x = r.x.get(l);
                    let n = w
                        .grid
                        .runs_in_box(x - w.r_max, x + w.r_max, &mut runs)
                        .expect("a point's query spans 3x3 columns");
                    for &(s, e) in &runs[..n] {
                        let (s, e) = (s as usize, e as usize);
                        let run = adhesion::Run {
                            x: &w.sorted[0][s..e],
                            y: &w.sorted[1][s..e],
                            z: &w.sorted[2][s..e],
                        };
                        let (ox, oy, oz) = (&mut fx[s..e], &mut fy[s..e], &mut fz[s..e]);
                        adhesion::gather_run_lanes(
                            &r.x, &one, run, ox, oy, oz, &mut acc, &mut near, w.r_min, w.r_max, w.s,
                        );
                    }
                }
            }
            let fi = &mut f[i];
            for l in 0..W {
                fi.x[l] += acc.x[l];
                fi.y[l] += acc.y[l];
                fi.z[l] += acc.z[l];
                wet[i][l] += (1.0 - wet[i][l]) * w.wet_gain * near[l];
            }
        }
    }
    // Pass: integrate; pinned points take the head's target.
    let head = &ctx.heads[s];
    let target = |i: usize| -> Option<L3> {
        if !lay.pinned_row[base + i] {
            return None;
        }
        let rest = &lay.rest_local[base + i];
        let mut t = L3::ZERO;
        for l in 0..W {
            t.set(l, head.transform_point3(rest.get(l)));
        }
        Some(t)
    };
    match ctx.integrator {
        Integrator::ImplicitEuler => {
            let sc = worker.band.as_mut().expect("band scratch allocated for implicit Euler");
            let iters = ctx.solver_iterations;
            implicit_euler_block::<AXIAL>(rows, f, params, &target, ctx.bend, ctx.g, ctx.h, iters, sc);
        }
        Integrator::Xpbd => {
            let prev = &mut worker.prev[..p];
            let lambda = &mut worker.lambda[..2 * p];
            lambda.fill([0.0; W]);
            for i in 0..p {
                let r = &mut rows[i];
                xpbd::predict_row(
                    &mut r.x,
                    &mut r.v,
                    &mut prev[i],
                    &f[i],
                    &params[i].inv_mass,
                    target(i).as_ref(),
                    ctx.g,
                    ctx.h,
                );
            }
            for _ in 0..ctx.solver_iterations.max(1) {
                for i in 0..p - 1 {
                    let (ra, rb) = rows.split_at_mut(i + 1);
                    let (wa, wb) = (&params[i].inv_mass, &params[i + 1].inv_mass);
                    xpbd::project(
                        &mut ra[i].x,
                        &mut rb[0].x,
                        wa,
                        wb,
                        &params[i].stretch,
                        &mut lambda[i],
                        ctx.h,
                    );
                }
                if ctx.bend {
                    for i in 0..p - 2 {
                        let (ra, rb) = rows.split_at_mut(i + 2);
                        let (wa, wb) = (&params[i].inv_mass, &params[i + 2].inv_mass);
                        xpbd::project(
                            &mut ra[i].x,
                            &mut rb[0].x,
                            wa,
                            wb,
                            &params[i].bend,
                            &mut lambda[p + i],
                            ctx.h,
                        );
                    }
                }
            }
            for i in 0..p {
                xpbd::finish_row(&rows[i].x, &mut rows[i].v, &prev[i], ctx.h);
            }
        }
        _ => {
            for i in 0..p {
                let r = &mut rows[i];
                let t = target(i);
                symplectic_euler_row(&mut r.x, &mut r.v, &f[i], &params[i].inv_mass, t.as_ref(), ctx.g, ctx.h);
            }
        }
    }
    let mut max_v2 = worker.max_v2;
    let mut check = 0.0f32;
    for i in 0..p {
        let r = &mut rows[i];
        // Pass: collide.
        for c in &ctx.placed[s * ctx.n_colliders..(s + 1) * ctx.n_colliders] {
            collide_row(&mut r.x, &mut r.v, &params[i].inv_mass, c, ctx.friction);
        }
        for l in 0..W {
            let v2 = r.v.x[l] * r.v.x[l] + r.v.y[l] * r.v.y[l] + r.v.z[l] * r.v.z[l];
            max_v2 = max_v2.max(v2);
            // Any NaN or inf in a lane makes the running sum non-finite.
            check += v2 + r.x.x[l] + r.x.y[l] + r.x.z[l];
        }
    }
    worker.max_v2 = max_v2;
    if !check.is_finite() {
        worker.nonfinite = true;
    }
}

/// The passes a step runs for these parameters, in order: both backends build their step
/// from this one list. `bend`: the scene has bend springs; `wet`: it holds water now.
pub fn pass_list(p: &SimParams, integrator: Integrator, bend: bool, wet: bool) -> Vec<Pass> {
    let mut v = Vec::new();
    if wet {
        v.push(Pass::WaterGrid);
    }
    if p.air_drag > 0.0 {
        v.push(Pass::Drag);
    }
    let explicit = integrator == Integrator::SymplecticEuler;
    if explicit && (p.stretch.stiffness > 0.0 || p.stretch.damping > 0.0) {
        v.push(Pass::StretchSprings);
    }
    if explicit && bend {
        v.push(Pass::BendSprings);
    }
    if wet {
        v.push(Pass::Adhesion);
    }
    v.push(match integrator {
        Integrator::ImplicitEuler => Pass::ImplicitSolve,
        _ => Pass::Integrate,
    });
    if integrator == Integrator::Xpbd {
        v.push(Pass::ProjectConstraints);
    }
    if !p.colliders.is_empty() {
        v.push(Pass::Collide);
    }
    if wet {
        v.push(Pass::WaterIntegrate);
        v.push(Pass::WaterCull);
    }
    v
}

/// Whether this CPU runs AVX2 (checked once per simulation).
fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Resolves [`Integrator::Auto`]: symplectic Euler when it is stable with a 10% margin for the
/// lightest free point at the substep of a 60 Hz frame, else implicit Euler.
pub fn resolve_integrator(p: &SimParams, groom: &crate::groom::Groom) -> Integrator {
    if p.integrator != Integrator::Auto {
        return p.integrator;
    }
    let min_mass = groom
        .masses()
        .iter()
        .zip(groom.pinned())
        .filter(|(_, &pin)| !pin)
        .map(|(&m, _)| m)
        .fold(f32::INFINITY, f32::min);
    let h = 1.0 / (60.0 * p.substeps as f32);
    if crate::params::explicit_limit(p, min_mass, h) < 0.9 * 4.0 {
        Integrator::SymplecticEuler
    } else {
        Integrator::ImplicitEuler
    }
}
