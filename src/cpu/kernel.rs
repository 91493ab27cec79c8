//! The CPU backend's block kernel: one substep of one block of 8 strands, pass by pass in the
//! pass list's order (drag, stretch and bend springs, adhesion, integrate, collide), on SIMD
//! lanes. `step.rs` schedules it over blocks and substeps.

use super::layout::{Layout, StateRow};
use crate::params::Integrator;
use crate::physics::bdf2::{explicit_lead, explicit_point, keep_push, Bdf2Blend, Bdf2Row};
use crate::physics::collide::{Colliders, Placed};
use crate::physics::implicit::{implicit_euler_block, BandScratch};
use crate::physics::integrate::symplectic_euler_row;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::spring::spring;
use crate::physics::xpbd;
use crate::physics::{absorb, adhesion};
use glam::Affine3A;

/// Most grid columns one row query walks (a row spanning ~6 cells a side); wider rows query
/// lane by lane (3 x 3 columns each, as cells are r_max wide).
const MAX_RUNS: usize = 49;

/// Scratch of one chunk of blocks (a thread runs several chunks a step), allocated at create
/// (water buffers at the first add).
#[derive(Debug, Default)]
pub struct Worker {
    pub(super) f: Vec<L3>,
    /// Reactions on particles from this chunk's blocks, in block order (then the order the
    /// kernel found them); summed per particle after every chunk is done.
    pub(super) reactions: Vec<adhesion::Reaction>,
    /// Each block's run of `reactions` and the slots it touches, in block order.
    pub(super) spans: Vec<super::slot_spans::SlotSpan>,
    pub(super) max_v2: f32,
    pub(super) nonfinite: bool,
    /// Banded system of one block (implicit Euler and BDF2 only).
    pub(super) band: Option<BandScratch>,
    /// Positions before the substep (XPBD only).
    pub(super) prev: Vec<L3>,
    /// Constraint multipliers, stretch then bend (XPBD only).
    pub(super) lambda: Vec<Lane>,
    /// Absorption demands from this chunk's blocks, in block order (held water only).
    pub(super) demands: Vec<absorb::Demand>,
    /// Each block's run of `demands` and the slots it names, in block order.
    pub(super) demand_spans: Vec<super::slot_spans::SlotSpan>,
}

impl Worker {
    /// Empties the lists a substep fills (reactions, absorption demands and their spans).
    pub(super) fn clear_lists(&mut self) {
        self.reactions.clear();
        self.spans.clear();
        self.demands.clear();
        self.demand_spans.clear();
    }

    /// Allocates the scratch `integrator` needs for blocks of `rows` rows (what is there
    /// stays: a switch back needs it again).
    pub(super) fn scratch_for(&mut self, integrator: Integrator, rows: usize) {
        if integrator.is_implicit() && self.band.is_none() {
            self.band = Some(BandScratch::new(rows));
        }
        if integrator == Integrator::XPBD && self.prev.is_empty() {
            self.prev = vec![L3::ZERO; rows];
            self.lambda = vec![[0.0; W]; 2 * rows];
        }
    }
}

/// Constant inputs of one substep.
pub(super) struct Ctx<'a> {
    pub(super) integrator: Integrator,
    pub(super) solver_iterations: u32,
    /// BDF2's blends for the frame's first substep (maybe a backward Euler restart) and for
    /// the others (from [`crate::physics::bdf2::Bdf2Clock`]).
    pub(super) bdf2: (Bdf2Blend, Bdf2Blend),
    pub(super) lay: &'a Layout,
    /// Per-row parameters: the layout's, or with held water's masses.
    pub(super) params: &'a [super::layout::ParamRow],
    pub(super) avx2: bool,
    pub(super) h: f32,
    pub(super) g: [f32; 3],
    /// Each hair point's air drag coefficient (per point, or per length of hair).
    pub(super) drag: crate::physics::per_length::PerLength,
    /// The wind this step, m/s (drag pulls hair toward it).
    pub(super) wind: [f32; 3],
    /// The liquid bridges (held water with bridges, some pair found).
    pub(super) cohesion: Option<&'a super::bridges::Cohesion<'a>>,
    pub(super) bend: bool,
    pub(super) heads: &'a [Affine3A],
    pub(super) placed: &'a [Placed],
    pub(super) n_colliders: usize,
    /// The SDF colliders and each substep's placements (SDFs per substep each).
    pub(super) sdfs: &'a [std::sync::Arc<crate::physics::sdf::Sdf>],
    pub(super) placed_sdfs: &'a [crate::physics::sdf::PlacedSdf],
    /// Skinned roots: pinned points follow these frames instead of the head.
    pub(super) roots: Option<&'a super::roots::Roots>,
    pub(super) friction: f32,
    pub(super) water: Option<WaterCtx<'a>>,
}

/// Water inputs of one substep (read-only while blocks run).
pub(super) struct WaterCtx<'a> {
    pub(super) grid: &'a crate::physics::grid::Grid,
    pub(super) sorted: &'a [Vec<f32>; 3],
    pub(super) r_min: f32,
    pub(super) r_max: f32,
    /// Eq. 2's strength by grid slot (each slot's drops where piles pull as one).
    pub(super) s: crate::physics::adhesion::Strength<'a>,
    /// Each hair point's share of eq. 2's pull: 1, or the hair it stands for over
    /// `water.adhesion_length`.
    pub(super) share: crate::physics::per_length::PerLength,
    /// Eq. 2's stability limit this substep (`physics/pull_limit.rs`).
    pub(super) limit: crate::physics::pull_limit::PullLimit,
    pub(super) wet_gain: f32,
    /// Absorption (held water on).
    pub(super) absorb: Option<AbsorbCtx<'a>>,
    /// Each point's bundle per row (`physics/bundles.rs`; empty: 1, no guides): a guide
    /// asks a drop for its bundle's water and pulls it with its bundle's hair.
    pub(super) bundle: &'a [Lane],
}

/// Absorption inputs of one substep (docs/WET_MODEL.md §2).
pub(super) struct AbsorbCtx<'a> {
    /// Particles' water in grid order, quanta.
    pub(super) mass: &'a [u32],
    pub(super) strength_per_quantum: f64,
    /// The fraction of a particle a point standing for `wet::ABSORB_LENGTH` of hair takes
    /// within `r_min` in a substep (`wet::absorb_take`, once per substep, not once per pair).
    pub(super) take: f32,
    /// Held water and hold limit per row, quanta (how full each point is at the substep's
    /// start).
    pub(super) held: &'a [[u32; W]],
    pub(super) hold: &'a [[u32; W]],
}

/// One substep of one block, compiled for the best instruction set this CPU has (AVX2 where
/// present, else the baseline). No FMA contraction happens in either, so both give the same
/// bits.
#[inline(always)]
pub(super) fn block_substep<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    history: &mut [Bdf2Row],
    worker: &mut Worker,
) {
    #[cfg(target_arch = "x86_64")]
    if ctx.avx2 {
        // SAFETY: `avx2` was set from `is_x86_feature_detected!("avx2")` at create.
        unsafe { block_substep_avx2::<AXIAL>(ctx, b, s, rows, wet, history, worker) };
        return;
    }
    block_substep_base::<AXIAL>(ctx, b, s, rows, wet, history, worker)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_substep_avx2<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    history: &mut [Bdf2Row],
    worker: &mut Worker,
) {
    block_substep_impl::<AXIAL>(ctx, b, s, rows, wet, history, worker)
}

#[inline(never)]
fn block_substep_base<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    history: &mut [Bdf2Row],
    worker: &mut Worker,
) {
    block_substep_impl::<AXIAL>(ctx, b, s, rows, wet, history, worker)
}

/// One substep of one block: forces → integrate → collide. The heart of the CPU backend.
#[inline(always)]
fn block_substep_impl<const AXIAL: bool>(
    ctx: &Ctx,
    b: usize,
    s: usize,
    rows: &mut [StateRow],
    wet: &mut [Lane],
    history: &mut [Bdf2Row],
    worker: &mut Worker,
) {
    let lay = ctx.lay;
    let p = lay.rows;
    let base = b * p;
    let params = &ctx.params[base..base + p];
    let f = &mut worker.f[..p];

    // Pass: drag toward the wind (or clear the force accumulators). The implicit solve takes
    // drag itself, implicitly.
    let [wx, wy, wz] = ctx.wind;
    let explicit_drag = !ctx.integrator.is_implicit();
    for (i, (fi, r)) in f.iter_mut().zip(rows.iter()).enumerate() {
        let c = if explicit_drag {
            ctx.drag.row(params, i)
        } else {
            [0.0; W]
        };
        for l in 0..W {
            fi.x[l] = c[l] * (wx - r.v.x[l]);
            fi.y[l] = c[l] * (wy - r.v.y[l]);
            fi.z[l] = c[l] * (wz - r.v.z[l]);
        }
    }
    // Pass: stretch springs (i, i+1) (XPBD projects them as constraints instead).
    // (Implicit Euler evaluates them inside its Newton iterations.)
    let springs_as_forces = ctx.integrator == Integrator::SYMPLECTIC_EULER;
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
    let lead = explicit_lead(ctx.integrator, ctx.h);
    // Pass: adhesion (eq. 2), gathered per hair point; reactions go to this worker's list
    // (summed per particle, in block order, before the particles move). BDF2 takes it at
    // x + h v, the step's end to O(h²) (`bdf2::explicit_point` says why).
    if let Some(w) = &ctx.water {
        for (i, r) in rows.iter().enumerate() {
            let x = if lead > 0.0 { explicit_point(r, lead) } else { r.x };
            // Which lanes can have a particle within r_max (SIMD prefilter), minus padding.
            let mut lanes = prefilter(ctx.avx2, w, &x) & lay.real_lanes[base + i] as u32;
            if lanes == 0 {
                continue;
            }
            // The wetness row this row may grow below, asked for now: the query and the
            // gather run while it comes (in lock step it is a cache miss, and waiting on it
            // at the end was 6 % of the big groom's kernel under rain). One line: `wet` is
            // `AlignedRows`.
            if w.wet_gain > 0.0 {
                super::prefetch::line(&wet[i]);
            }
            // Row path: one query for the lanes' bounds, each particle against all lanes at once.
            // Morton-ordered strands keep most rows compact; a row too wide for MAX_RUNS columns
            // goes lane by lane.
            let (lo, hi, mask) = bounds_and_mask(ctx.avx2, &x, lanes);
            // Each lane's pull: its mask times its share of the hair (1 per point).
            let share = w.share.row(params, i);
            let weight: Lane = std::array::from_fn(|l| mask[l] * share[l]);
            // In a guide groom each point stands for its bundle's strands: it pulls a drop
            // back with their hair (eq. 2's reaction), and asks it for their water.
            let bundle = w.bundle.get(base + i);
            // Absorption asks in proportion to the hair each point stands for: its own, times
            // its bundle.
            let absorb_share = match &w.absorb {
                Some(_) => {
                    let own = crate::physics::wet::ABSORB_SHARE.row(params, i);
                    match bundle {
                        Some(b) => std::array::from_fn(|l| own[l] * b[l]),
                        None => own,
                    }
                }
                None => [0.0; W],
            };
            let mut runs = [(0u32, 0u32); MAX_RUNS];
            let mut acc = L3::ZERO;
            let mut near = [0.0f32; W];
            let mut wet_row = w.absorb.as_ref().map(|a| absorb::WetRow {
                mass: a.mass,
                strength_per_quantum: a.strength_per_quantum,
                water: &a.held[base + i],
                hold: &a.hold[base + i],
                share: &absorb_share,
                sat: None,
                first_point: ((base + i) * W) as u32,
                take: a.take,
                out: &mut worker.demands,
            });
            let reactions = &mut worker.reactions;
            let inv_mass = &params[i].inv_mass;
            if let Some(n) = w.grid.runs_in_box(lo - w.r_max, hi + w.r_max, &mut runs) {
                gather_runs(
                    ctx.avx2,
                    w,
                    &x,
                    &mask,
                    &weight,
                    bundle,
                    inv_mass,
                    &runs[..n],
                    reactions,
                    &mut acc,
                    &mut near,
                    wet_row.as_mut(),
                );
            } else {
                while lanes != 0 {
                    let l = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    let (mut one, mut one_weight) = ([0.0f32; W], [0.0f32; W]);
                    one[l] = 1.0;
                    one_weight[l] = share[l];
                    let p = x.get(l);
                    let n = w
                        .grid
                        .runs_in_box(p - w.r_max, p + w.r_max, &mut runs)
                        .expect("a point's query spans 3x3 columns");
                    gather_runs(
                        ctx.avx2,
                        w,
                        &x,
                        &one,
                        &one_weight,
                        bundle,
                        inv_mass,
                        &runs[..n],
                        reactions,
                        &mut acc,
                        &mut near,
                        wet_row.as_mut(),
                    );
                }
            }
            let fi = &mut f[i];
            for l in 0..W {
                fi.x[l] += acc.x[l];
                fi.y[l] += acc.y[l];
                fi.z[l] += acc.z[l];
            }
            // The wetness only where it grows (the paper model, a lane within reach): adding
            // zero leaves it as it is, and its row is otherwise never read here (in lock step
            // a cache miss a row; with held water, whose wetness is the saturation, every
            // passing row's).
            if w.wet_gain > 0.0 && near.iter().any(|&n| n > 0.0) {
                for l in 0..W {
                    wet[i][l] += (1.0 - wet[i][l]) * w.wet_gain * near[l];
                }
            }
        }
    }
    // Pass: cohesion (liquid bridges: each wet point's pull from its neighbours' positions at
    // the substep's start).
    if let Some(c) = ctx.cohesion {
        c.pull_block(b, base, ctx.avx2, f);
    }
    // Pass: integrate; pinned points take the head's target (or their root frame's).
    let head = &ctx.heads[s];
    let a = (s + 1) as f32 / ctx.heads.len() as f32;
    let target = |i: usize| pinned_target(ctx, b, i, a, head);
    match ctx.integrator {
        Integrator::IMPLICIT_EULER | Integrator::BDF2 => {
            let sc = worker.band.as_mut().expect("band scratch allocated for implicit Euler");
            let iters = ctx.solver_iterations;
            let (mut h, mut bdf2) = (ctx.h, None);
            if ctx.integrator == Integrator::BDF2 && !history.is_empty() {
                // BDF2: backward Euler from the blend of this start and the last.
                let blend = if s == 0 { ctx.bdf2.0 } else { ctx.bdf2.1 };
                h = blend.h;
                bdf2 = Some((&mut *history, blend.b));
            }
            let drag = (ctx.drag, ctx.wind);
            implicit_euler_block::<AXIAL>(rows, f, params, &target, ctx.bend, ctx.g, drag, h, iters, bdf2, sc);
        }
        Integrator::XPBD => {
            let prev = &mut worker.prev[..p];
            let lambda = &mut worker.lambda[..2 * p];
            lambda.fill([0.0; W]);
            // The rows without a pinned lane, then those with one (as symplectic Euler's).
            let pinned = &lay.pinned_row[base..base + p];
            let (g, h) = (ctx.g, ctx.h);
            for i in (0..p).filter(|&i| !pinned[i]) {
                let r = &mut rows[i];
                xpbd::predict_row(&mut r.x, &mut r.v, &mut prev[i], &f[i], &params[i].inv_mass, None, g, h);
            }
            for i in (0..p).filter(|&i| pinned[i]) {
                let (r, t) = (&mut rows[i], target(i));
                let w = &params[i].inv_mass;
                xpbd::predict_row(&mut r.x, &mut r.v, &mut prev[i], &f[i], w, t.as_ref(), g, h);
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
            // The rows without a pinned lane integrate with no target (a simpler body: on the
            // big groom under rain one loop over all rows with the target an `Option` took 4-6 %
            // more), then the pinned rows. Not through `target`: a closure used in three
            // places was left a call per row, compiled without AVX2.
            let pinned = &lay.pinned_row[base..base + p];
            let (g, h) = (ctx.g, ctx.h);
            for i in (0..p).filter(|&i| !pinned[i]) {
                let r = &mut rows[i];
                symplectic_euler_row(&mut r.x, &mut r.v, &f[i], &params[i].inv_mass, None, g, h);
            }
            for i in (0..p).filter(|&i| pinned[i]) {
                let r = &mut rows[i];
                let t = pinned_target(ctx, b, i, a, head);
                symplectic_euler_row(&mut r.x, &mut r.v, &f[i], &params[i].inv_mass, t.as_ref(), g, h);
            }
        }
    }
    // Per lane, so that neither is a serial chain through every lane of every row.
    let mut max_v2 = [worker.max_v2; W];
    let mut check = [0.0f32; W];
    let ns = ctx.sdfs.len();
    let colliders = Colliders {
        placed: &ctx.placed[s * ctx.n_colliders..(s + 1) * ctx.n_colliders],
        sdfs: ctx.sdfs,
        placed_sdfs: &ctx.placed_sdfs[s * ns..(s + 1) * ns],
    };
    // BDF2's history keeps the substep's displacement, so it follows the pushes.
    let keep = ctx.integrator == Integrator::BDF2 && !history.is_empty() && colliders.any();
    for i in 0..p {
        let r = &mut rows[i];
        // Pass: collide.
        if keep {
            let before = r.x;
            colliders.push_out_row(&mut r.x, &mut r.v, &params[i].inv_mass, ctx.friction);
            keep_push(&mut history[i], &before, &r.x);
        } else {
            colliders.push_out_row(&mut r.x, &mut r.v, &params[i].inv_mass, ctx.friction);
        }
        for l in 0..W {
            let v2 = r.v.x[l] * r.v.x[l] + r.v.y[l] * r.v.y[l] + r.v.z[l] * r.v.z[l];
            // A compare and select (one max instruction): a NaN `v2` keeps the last, as
            // `f32::max` would, and `check` catches it.
            max_v2[l] = if v2 > max_v2[l] { v2 } else { max_v2[l] };
            // `blown_up`, lane-wise: each product is 0 unless its factor is NaN or inf (a
            // speed whose square overflows included), and a sum of zeros cannot overflow.
            check[l] += v2 * 0.0 + r.x.x[l] * 0.0 + r.x.y[l] * 0.0 + r.x.z[l] * 0.0;
        }
    }
    worker.max_v2 = max_v2.iter().fold(0.0, |a: f32, &b| a.max(b));
    if !check.iter().sum::<f32>().is_finite() {
        worker.nonfinite = true;
    }
}

/// Where row `i` of block `b` is held at substep fraction `a` if it is pinned: the head's
/// placement of its rest point (`head`), or its skinned root frame's.
#[inline(always)]
fn pinned_target(ctx: &Ctx, b: usize, i: usize, a: f32, head: &Affine3A) -> Option<L3> {
    let row = b * ctx.lay.rows + i;
    ctx.lay.pinned_row[row].then(|| pinned_place(ctx, b, i, row, a, head))
}

/// [`pinned_target`] of a pinned row. Never inlined: inlined, LLVM computed it for every row
/// (a read of the row's 96-byte rest row and a transform) and kept it on the pinned rows
/// only, whatever the loop around it, which in lock step cost the big groom 10-20 % of its
/// block kernel. A call is not speculated, and it is made on pinned rows only (a strand's
/// first point or two).
#[inline(never)]
fn pinned_place(ctx: &Ctx, b: usize, i: usize, row: usize, a: f32, head: &Affine3A) -> L3 {
    match ctx.roots {
        Some(r) => r.target(ctx.lay.rows, b, i, a),
        None => ctx.lay.rest_local[row].transformed(head),
    }
}

/// The water grid's prefilter for a row: which lanes may have a particle within `r_max`.
/// `avx2`: its AVX2 form (the same bits).
#[inline(always)]
fn prefilter(avx2: bool, w: &WaterCtx, x: &L3) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` comes from `is_x86_feature_detected!("avx2")` at create.
        return unsafe { w.grid.may_have_near_lanes_avx2(x, w.r_max) };
    }
    let _ = avx2;
    w.grid.may_have_near_lanes(x, w.r_max)
}

/// The bounds of the lanes of `x` whose bit is set in `lanes`, and those lanes as a mask of
/// 1.0 and 0.0. `avx2`: its AVX2 form (the same bits).
#[inline(always)]
fn bounds_and_mask(avx2: bool, x: &L3, lanes: u32) -> (glam::Vec3, glam::Vec3, Lane) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` comes from `is_x86_feature_detected!("avx2")` at create.
        return unsafe { crate::physics::lanes_avx2::bounds_and_mask(x, lanes) };
    }
    let _ = avx2;
    let (lo, hi) = x.bounds_of(lanes);
    (lo, hi, std::array::from_fn(|l| (lanes >> l & 1) as f32))
}

/// Eq. 2 between the lanes of `x` in `mask` and the particles of grid `runs` (slices of the
/// grid-ordered particles), under its stability limit (`physics/pull_limit.rs`, from the
/// row's `inv_mass`): adds the hair's forces to `acc`, marks `near` lanes, and appends the
/// particles' reactions to `reactions` (this worker's), each lane's times its `bundle` in a
/// guide groom. `avx2`: run the gather's AVX2 form
/// (the same bits).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn gather_runs(
    avx2: bool,
    w: &WaterCtx,
    x: &L3,
    mask: &[f32; W],
    weight: &[f32; W],
    bundle: Option<&[f32; W]>,
    inv_mass: &[f32; W],
    runs: &[(u32, u32)],
    reactions: &mut Vec<adhesion::Reaction>,
    acc: &mut L3,
    near: &mut [f32; W],
    wet_row: Option<&mut absorb::WetRow>,
) {
    let sorted = [&w.sorted[0][..], &w.sorted[1][..], &w.sorted[2][..]];
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` comes from `is_x86_feature_detected!("avx2")` at create.
        unsafe {
            crate::physics::adhesion_avx2::gather_row_lanes(
                x, mask, weight, bundle, inv_mass, &w.limit, runs, sorted, reactions, acc, near, w.r_min, w.r_max, w.s,
                wet_row,
            )
        };
        return;
    }
    let _ = avx2;
    adhesion::gather_row_lanes(
        x, mask, weight, bundle, inv_mass, &w.limit, runs, sorted, reactions, acc, near, w.r_min, w.r_max, w.s, wet_row,
    );
}
