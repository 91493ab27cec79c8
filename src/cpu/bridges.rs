//! Liquid bridges on the CPU (docs/WET_MODEL.md §5): a hashed grid over the wet hair points
//! finds each point's nearest wet points of other strands (pass `hair_grid`, once per step,
//! each point searched in turn); every substep each mutual pair pulls its two points together
//! (pass `cohesion`). The pass packs the wet points' positions before the step's first
//! substep; the block kernel gathers each of its wet points' pulls from them and, after its
//! substep, writes its wet points' new positions for the next (`Cohesion`), so the positions
//! are read from the state once a step instead of once a substep, and no force per row is
//! written and read back. Exists only when bridges are on.

use super::cohesion::{self, Pairs};
use super::held_rows;
use super::layout::{Layout, ParamRow, StateRow};
use super::pool::{for_chunks, for_chunks2, Pool};
use super::prefetch;
use crate::physics::hash_grid::HashGrid;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::wet;
use glam::Vec3;
use rayon::prelude::*;

pub use crate::physics::wet::{BRIDGE_SEARCH_TURNS as SEARCH_TURNS, MAX_BRIDGES};

/// Points searched per parallel task.
const CHUNK: usize = 512;

/// Wet points from which the grid over them is built on the pool: below, the pool's start
/// costs more than it saves (on 2 threads the paper scene's 7,500 points took 154 µs on
/// the pool and 114 µs on one thread, the big groom's 36,000 230-290 µs and 200 µs).
const PARALLEL_GRID: usize = 1 << 17;

/// Rows per parallel task of the listing (its marking and filling passes).
const ROWS_PER_TASK: usize = 256;

/// Pairs found this step and the force they give.
#[derive(Debug)]
pub struct Bridges {
    grid: HashGrid,
    /// The wet free points (row index times `W` plus lane), in index order.
    point: Vec<u32>,
    /// Last step's `point` (the points whose places the listing clears).
    last_point: Vec<u32>,
    /// Scratch of the listing: per row, a bit per lane that takes part this step.
    wet_rows: Vec<u8>,
    /// Per row, a bit per lane that is a free point of a strand (not padding, not pinned):
    /// the listing reads this byte, not the lane's inverse mass in the row's parameters (a
    /// cache line a row).
    free_lanes: Vec<u8>,
    /// Their positions at the step's start (the grid's input).
    pos: Vec<Vec3>,
    /// Their strands (block times `W` plus lane: one number per strand).
    strand: Vec<u32>,
    /// Their saturation, length of hair and inverse mass.
    traits: Vec<WetTraits>,
    /// Per point index: its nearest wet points of other strands as of its last search, and
    /// its place in `point` this step (one cache line, read together by the mutual test).
    near: Vec<Near>,
    /// Per wet point (by place in `point`): whether it searches this step (its turn, or it
    /// has no neighbour), marked by the listing, which reads its record anyway.
    searches: Vec<bool>,
    /// This step's searches: places in `point`, and what each found.
    turn: Vec<u32>,
    found: Vec<([u32; MAX_BRIDGES], u8)>,
    /// Per wet point: its mutual pairs (places in `point`, in its nearest's order), each with
    /// its spring coefficient, N/m (the same for both directions).
    pairs: Vec<Pairs>,
    /// Whether any pair was found this step.
    bridged: bool,
    /// Scratch of the listing: each run of rows' first place among the wet points.
    run_start: Vec<u32>,
    /// Scratch: what stiffness each wet point may still take.
    room: Vec<f32>,
    /// The wet points' positions at the substep's start (by place in `point`), and where the
    /// blocks write them at the substep's end for the next.
    xs: Vec<Vec3>,
    xs_next: Vec<Vec3>,
    /// Per block, its first wet point's place (its wet points are a run of `point`, which is
    /// in index order); one more entry ends the last block's run.
    block_start: Vec<u32>,
    /// How far along its velocity a point is taken this step (BDF2's substep, else 0).
    ahead: f32,
    /// Steps since the last reset (whose turn it is).
    step: u32,
    /// Each point's length of hair, m, per row (half of each adjacent segment).
    length: Vec<[f32; W]>,
    /// Per point index: its host point index (the search turn and the nearest's tie-break,
    /// shared with the GPU, which numbers points as the host does).
    host: Vec<u32>,
    kappa: f32,
    d_b: f32,
}

impl Bridges {
    /// Empty, with each point's length of hair from the rest pose.
    pub fn new(lay: &Layout, kappa: f32, d_b: f32) -> Bridges {
        let n_rows = lay.blocks * lay.rows;
        let mut length = vec![[0.0f32; W]; n_rows];
        let mut host = vec![u32::MAX; n_rows * W];
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let n = lay.strand_points(s);
            for i in 0..n {
                host[(b * lay.rows + i) * W + l] = lay.strand_first[s] + i as u32;
            }
            for i in 0..n.saturating_sub(1) {
                let (r0, r1) = (b * lay.rows + i, b * lay.rows + i + 1);
                let seg = (lay.rest_local[r1].get(l) - lay.rest_local[r0].get(l)).length();
                length[r0][l] += 0.5 * seg;
                length[r1][l] += 0.5 * seg;
            }
        }
        let free_lanes = lay
            .params
            .iter()
            .zip(&lay.real_lanes)
            .map(|(row, &real)| (0..W).fold(0u8, |m, l| m | (((row.inv_mass[l] > 0.0) as u8) << l)) & real)
            .collect();
        Bridges {
            // Cells of twice the reach: a query then visits 2 x 2 x 2 cells (about 7 bucket
            // lookups, each a likely cache miss) instead of up to 27 with cells of `d_b`
            // (measured on the paper scene: about 24); it scans a few more points, in runs.
            grid: HashGrid::new(2.0 * d_b),
            point: Vec::new(),
            last_point: Vec::new(),
            wet_rows: vec![0; n_rows],
            free_lanes,
            pos: Vec::new(),
            strand: Vec::new(),
            traits: Vec::new(),
            near: vec![Near::NONE; n_rows * W],
            searches: Vec::new(),
            turn: Vec::new(),
            found: Vec::new(),
            pairs: Vec::new(),
            bridged: false,
            run_start: Vec::new(),
            room: Vec::new(),
            xs: Vec::new(),
            xs_next: Vec::new(),
            block_start: vec![0; lay.blocks + 1],
            ahead: 0.0,
            step: 0,
            length,
            host,
            kappa,
            d_b,
        }
    }

    /// Each row's free lanes, and where the pass after the substeps writes the next step's
    /// marks (`held_rows::bridge_marks`), which `find_pairs` then takes as given.
    pub fn marks(&mut self) -> (&[u8], &mut [u8]) {
        (&self.free_lanes, &mut self.wet_rows)
    }

    /// How many points searched this step.
    pub fn searched(&self) -> u32 {
        self.turn.len() as u32
    }

    /// Whether any pair was found this step (else the cohesion pass is skipped).
    pub fn active(&self) -> bool {
        self.bridged
    }

    /// No pair, and the search turns start over (a reset simulation replays like a new one).
    pub fn reset(&mut self) {
        self.forget_points();
        self.near.iter_mut().for_each(|n| *n = Near::NONE);
        self.step = 0;
    }

    /// Drops the last step's wet points and pairs: their places are unmapped (each point's
    /// nearest are kept for the search turns).
    fn forget_points(&mut self) {
        for &p in &self.point {
            self.near[p as usize].local = u32::MAX;
        }
        self.point.clear();
        self.last_point.clear();
        self.pos.clear();
        self.strand.clear();
        self.traits.clear();
        self.searches.clear();
        self.block_start.iter_mut().for_each(|s| *s = 0);
        self.pairs.clear();
        self.bridged = false;
    }

    /// Lists this step's wet free points (those holding water enough to bridge,
    /// [`wet::can_bridge`]) in index order with their positions, strands, saturations and
    /// lengths, and their places in `near`; a point listed last step and no longer wet
    /// forgets its place and its nearest. Pinned points (roots) take no part:
    /// a bridge cannot move them, and the scalp is where hair is densest. In two passes over
    /// runs of rows on the pool: mark each row's wet lanes and count them (reading only the
    /// held water, and last step's points), then fill each run's own part of the lists from
    /// its marked rows. `near` (32 bytes a point of the whole groom) is touched only at points
    /// listed now or last step: sweeping all of it twice was a quarter of the pass on a big
    /// groom. The fill also marks which points search in step `turn` (their records are in
    /// hand: a separate serial sweep reading them again cost the big groom 1.8 ms a step).
    #[allow(clippy::too_many_arguments)]
    fn list_wet(
        &mut self,
        lay: &Layout,
        state: &[StateRow],
        held: &[[u32; W]],
        capacity: &[[u32; W]],
        params: &[ParamRow],
        turn: u32,
        marked: bool,
        pool: Option<&Pool>,
    ) {
        let free = &self.free_lanes;
        std::mem::swap(&mut self.point, &mut self.last_point);
        let last = &self.last_point[..];
        let slots = ROWS_PER_TASK * W;
        // Pass 1: each row's wet lanes (unless `marked`: the pass after the last step's
        // substeps wrote them) and each run's count; last step's points forget.
        let mark = |c: usize, near: &mut [Near], rows: &mut [u8], count: &mut u32| {
            let r0 = c * ROWS_PER_TASK;
            let n = rows.len();
            if !marked {
                held_rows::bridge_marks(&held[r0..r0 + n], &capacity[r0..r0 + n], &free[r0..r0 + n], rows);
            }
            *count = rows.iter().map(|m| m.count_ones()).sum();
            let lo = last.partition_point(|&p| (p as usize) < r0 * W);
            let hi = lo + last[lo..].partition_point(|&p| (p as usize) < (r0 + rows.len()) * W);
            // A point still wet gets its new place in the fill; only those that left are
            // touched here (each a likely cache miss: `near` is 32 bytes a point of the
            // groom). Without nearest, no pair reads a left point's place.
            for &p in &last[lo..hi] {
                let (k, l) = (p as usize - r0 * W, p as usize % W);
                if rows[k / W] & (1 << l) == 0 {
                    near[k].local = u32::MAX;
                    near[k].n = 0;
                    near[k].searched = 0;
                }
            }
        };
        let runs = self.near.len().div_ceil(slots);
        self.run_start.clear();
        self.run_start.resize(runs, 0);
        let (near, rows, counts) = (&mut self.near, &mut self.wet_rows, &mut self.run_start);
        match pool {
            Some(pool) => pool.install(|| {
                near.par_chunks_mut(slots)
                    .zip(rows.par_chunks_mut(ROWS_PER_TASK))
                    .zip(counts.par_iter_mut())
                    .enumerate()
                    .for_each(|(c, ((n, m), k))| mark(c, n, m, k))
            }),
            None => near
                .chunks_mut(slots)
                .zip(rows.chunks_mut(ROWS_PER_TASK))
                .zip(counts.iter_mut())
                .enumerate()
                .for_each(|(c, ((n, m), k))| mark(c, n, m, k)),
        }
        let mut total = 0;
        for c in self.run_start.iter_mut() {
            (*c, total) = (total, total + *c);
        }
        // Each block's first wet point (a byte per row: fast next to the passes above).
        let mut first = 0u32;
        for (b, rows) in self.wet_rows.chunks(lay.rows).enumerate() {
            self.block_start[b] = first;
            first += rows.iter().map(|m| m.count_ones()).sum::<u32>();
        }
        self.block_start[lay.blocks] = first;
        let total = total as usize;
        self.point.resize(total, 0);
        self.pos.resize(total, Vec3::ZERO);
        self.strand.resize(total, 0);
        self.traits.resize(total, WetTraits::default());
        self.searches.resize(total, false);
        // The pairs are only read while some were found; the mutual test below rewrites them.
        self.bridged = false;
        // Pass 2: each run fills its own part of the lists from its marked rows.
        type Part<'a> = (
            &'a mut [u32],
            &'a mut [Vec3],
            &'a mut [u32],
            &'a mut [WetTraits],
            &'a mut [bool],
        );
        let mut parts: Vec<Part> = Vec::with_capacity(runs);
        let mut rest: Part = (
            &mut self.point,
            &mut self.pos,
            &mut self.strand,
            &mut self.traits,
            &mut self.searches,
        );
        for c in 0..runs {
            let end = self.run_start.get(c + 1).map_or(total, |&e| e as usize);
            let len = end - self.run_start[c] as usize;
            let (a0, b0) = std::mem::take(&mut rest.0).split_at_mut(len);
            let (a1, b1) = std::mem::take(&mut rest.1).split_at_mut(len);
            let (a2, b2) = std::mem::take(&mut rest.2).split_at_mut(len);
            let (a3, b3) = std::mem::take(&mut rest.3).split_at_mut(len);
            let (a4, b4) = std::mem::take(&mut rest.4).split_at_mut(len);
            parts.push((a0, a1, a2, a3, a4));
            rest = (b0, b1, b2, b3, b4);
        }
        let (length, start, marks, host) = (&self.length, &self.run_start, &self.wet_rows, &self.host);
        let fill = |c: usize, near: &mut [Near], part: Part| {
            let (point, pos, strand, traits, searches) = part;
            if point.is_empty() {
                return;
            }
            let r0 = c * ROWS_PER_TASK;
            let rows = near.len() / W;
            // The marked rows are sparse (under rain, the big groom's 40,000 wet points lie
            // in at most a fifth of its rows), and each row's records missed the cache one
            // after another: the next marked rows' are asked for ahead.
            let from = Sources {
                state,
                held,
                capacity,
                params,
                length,
                host,
            };
            let (mut ahead, mut pending) = (0, 0);
            let mut i = 0;
            for k in 0..rows {
                while ahead < rows && pending < LIST_AHEAD {
                    let r = r0 + ahead;
                    if marks[r] != 0 {
                        from.prefetch(r, &near[ahead * W..], marks[r]);
                        pending += 1;
                    }
                    ahead += 1;
                }
                let r = r0 + k;
                let mut m = marks[r];
                pending -= (m != 0) as usize;
                while m != 0 {
                    let l = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let me = &mut near[k * W + l];
                    me.local = start[c] + i as u32;
                    let searched = me.searched != 0;
                    searches[i] = wet::bridge_searches(host[r * W + l], turn, me.n as u32, searched);
                    point[i] = (r * W + l) as u32;
                    pos[i] = state[r].x.get(l);
                    strand[i] = ((r / lay.rows) * W + l) as u32;
                    traits[i] = WetTraits {
                        sat: wet::saturation(held[r][l], capacity[r][l]).min(1.0),
                        len: length[r][l],
                        inv_mass: params[r].inv_mass[l],
                    };
                    i += 1;
                }
            }
        };
        let near = &mut self.near;
        match pool {
            Some(pool) => pool.install(|| {
                near.par_chunks_mut(slots)
                    .zip(parts.into_par_iter())
                    .enumerate()
                    .for_each(|(c, (n, p))| fill(c, n, p))
            }),
            None => near
                .chunks_mut(slots)
                .zip(parts)
                .enumerate()
                .for_each(|(c, (n, p))| fill(c, n, p)),
        }
    }

    /// Pass `hair_grid`: searches this step's turn of wet free points (and every wet point with
    /// no neighbour yet) for its [`MAX_BRIDGES`] nearest wet points of other strands within the
    /// bridge length, keeps the pairs that are each among the other's nearest, in point order,
    /// and gives each its coefficient: the bridge's stiffness `4 kappa l min(s_i, s_j) / d_b`
    /// (peak pull `kappa l s` at `d_b / 2`), capped so that no point's bridges together exceed
    /// a quarter of what an explicit substep `h` holds stably (`m / (4 h^2)`, shared among its
    /// bridges). `params` are the rows the kernel reads this step (inverse masses with the
    /// water; 0 pinned). `any_held`: whether any point may hold water; when none does and
    /// none took part last step, nothing is listed (the search turns still count the step).
    /// `marked`: the rows' marks of who takes part are already written for this water
    /// ([`Bridges::marks`]).
    #[allow(clippy::too_many_arguments)]
    pub fn find_pairs(
        &mut self,
        lay: &Layout,
        state: &[StateRow],
        held: &[[u32; W]],
        capacity: &[[u32; W]],
        params: &[ParamRow],
        h: f32,
        any_held: bool,
        marked: bool,
        pool: Option<&Pool>,
    ) {
        // No search this step until the turn's list is made (`searched` reads it).
        self.turn.clear();
        if !any_held && self.point.is_empty() {
            self.step = self.step.wrapping_add(1);
            return;
        }
        let turn = self.step % SEARCH_TURNS;
        self.list_wet(lay, state, held, capacity, params, turn, marked, pool);
        self.step = self.step.wrapping_add(1);
        if self.point.len() < 2 {
            return;
        }
        let (grid, pos) = (&mut self.grid, &self.pos);
        match pool.filter(|_| pos.len() >= PARALLEL_GRID) {
            Some(pool) => pool.install(|| grid.build(pos, true)),
            None => grid.build(pos, false),
        }
        let searching = self.searches.iter().enumerate().filter(|&(_, &s)| s);
        self.turn.extend(searching.map(|(i, _)| i as u32));
        self.found.clear();
        self.found.resize(self.turn.len(), ([0; MAX_BRIDGES], 0));
        let (grid, point, strand, pos, turns) = (&self.grid, &self.point, &self.strand, &self.pos, &self.turn);
        let (d_b, host) = (self.d_b, &self.host[..]);
        let search = |k0: usize, out: &mut [([u32; MAX_BRIDGES], u8)]| {
            for (k, (near, n)) in out.iter_mut().enumerate() {
                let i = turns[k0 + k] as usize;
                let c = Candidates { point, strand, host };
                *n = nearest_of(grid, pos[i], &c, strand[i], d_b, near) as u8;
            }
        };
        for_chunks(pool, &mut self.found, CHUNK, search);
        record_found(&mut self.near, &self.point, &self.turn, &self.found, pool);
        // Keep a pair only when each is among the other's nearest and both are wet (a dry
        // point has no nearest): the bridges are symmetric, so each pair's two forces are
        // exact negatives. Point by point in parallel; each keeps its nearest's order.
        // With each point's pairs, what stiffness it may take: m / (4 h^2 n).
        // The mutual test writes every record whole, so only new ones are made here: clearing
        // first wrote every record twice, on one thread (78 MB a step on the soaked big groom).
        let (near, traits) = (&self.near[..], &self.traits);
        self.pairs.resize(self.point.len(), Pairs::NONE);
        self.room.resize(self.point.len(), 0.0);
        let mutual = |i0: usize, out: &mut [Pairs], room: &mut [f32]| {
            for (k, (out, room)) in out.iter_mut().zip(room).enumerate() {
                let p = point[i0 + k];
                let me = &near[p as usize];
                prefetch_nearest(near, point, i0 + k + PREFETCH_AHEAD);
                // Branch-free over all six slots (a slot past a count holds a valid index):
                // the counts vary point to point, and mispredicted exits cost more than the
                // few extra compares, and kept the next points' loads from starting early.
                let (mut j, mut n) = ([0u32; MAX_BRIDGES], 0usize);
                for m in 0..MAX_BRIDGES {
                    let other = &near[me.q[m] as usize];
                    let mut has = false;
                    for t in 0..MAX_BRIDGES {
                        has |= (t < other.n as usize) & (other.q[t] == p);
                    }
                    let hit = (m < me.n as usize) & has;
                    let slot = n.min(MAX_BRIDGES - 1);
                    j[slot] = if hit { other.local } else { j[slot] };
                    n += hit as usize;
                }
                out.j = j;
                out.c = [0.0; MAX_BRIDGES];
                out.n = n as u32;
                *room = 1.0 / (traits[i0 + k].inv_mass * 4.0 * h * h * n.max(1) as f32);
            }
        };
        for_chunks2(pool, &mut self.pairs, &mut self.room, CHUNK, mutual);
        // Whether any: where bridges hold, the first few points answer (the count of them
        // read every record again, on one thread).
        self.bridged = self.pairs.iter().any(|p| p.n > 0);
        let (room, tr, kappa, d_b) = (&self.room, &self.traits, self.kappa, self.d_b);
        let coef = |i0: usize, out: &mut [Pairs]| {
            for (k, out) in out.iter_mut().enumerate() {
                let i = i0 + k;
                for m in 0..out.n as usize {
                    let j = out.j[m] as usize;
                    let l = 0.5 * (tr[i].len + tr[j].len);
                    let stiff = wet::bridge_stiffness(kappa, l, tr[i].sat, tr[j].sat, d_b);
                    out.c[m] = stiff.min(room[i].min(room[j]));
                }
            }
        };
        for_chunks(pool, &mut self.pairs, CHUNK, coef);
    }

    /// Pass `cohesion`, its part before the substeps: packs the wet points' positions at the
    /// step's start (with `ahead` > 0, BDF2's, at `x + ahead v`: physics/bdf2.rs
    /// `explicit_point` says why), read by the block kernel's pulls ([`Cohesion`]). The
    /// kernel writes the later substeps' positions itself.
    pub fn pack(&mut self, state: &[StateRow], ahead: f32, pool: Option<&Pool>) {
        self.ahead = ahead;
        self.xs.clear();
        self.xs.resize(self.point.len(), Vec3::ZERO);
        let point = &self.point;
        let pack = |i0: usize, out: &mut [Vec3]| {
            for (k, x) in out.iter_mut().enumerate() {
                let p = point[i0 + k] as usize;
                *x = position_ahead(&state[p / W], p % W, ahead);
            }
        };
        for_chunks(pool, &mut self.xs, 4 * CHUNK, pack);
        // The blocks a step leaves out (guides beyond a lowered simulated fraction) do not
        // move, so both buffers hold their positions from here on.
        self.xs_next.clear();
        self.xs_next.extend_from_slice(&self.xs);
    }

    /// What the block kernel reads to pull its wet points this substep, and where it writes
    /// their positions for the next: `next` cut into each chunk's run (`chunk_blocks` blocks a
    /// chunk).
    pub fn cohesion(&mut self, chunk_blocks: usize) -> (Cohesion<'_>, Vec<&mut [Vec3]>) {
        let starts = &self.block_start;
        let blocks = starts.len() - 1;
        let mut next = Vec::with_capacity(blocks.div_ceil(chunk_blocks.max(1)));
        let mut rest = &mut self.xs_next[..];
        for b0 in (0..blocks).step_by(chunk_blocks.max(1)) {
            let b1 = (b0 + chunk_blocks).min(blocks);
            let (part, tail) = std::mem::take(&mut rest).split_at_mut((starts[b1] - starts[b0]) as usize);
            next.push(part);
            rest = tail;
        }
        let c = Cohesion {
            xs: &self.xs,
            pairs: &self.pairs,
            point: &self.point,
            block_start: starts,
            d_b: self.d_b,
            ahead: self.ahead,
        };
        (c, next)
    }

    /// The positions the blocks wrote become the next substep's.
    pub fn next_substep(&mut self) {
        std::mem::swap(&mut self.xs, &mut self.xs_next);
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.grid.bytes()
            + 4 * (self.point.capacity() + self.last_point.capacity() + self.strand.capacity())
            + 4 * (self.turn.capacity() + self.room.capacity())
            + self.searches.capacity()
            + self.wet_rows.capacity()
            + self.free_lanes.capacity()
            + std::mem::size_of::<Near>() * self.near.capacity()
            + std::mem::size_of::<Pairs>() * self.pairs.capacity()
            + (4 * MAX_BRIDGES + 1) * self.found.capacity()
            + 12 * (self.pos.capacity() + self.xs.capacity() + self.xs_next.capacity())
            + 4 * self.block_start.capacity()
            + std::mem::size_of::<WetTraits>() * self.traits.capacity()
            + 4 * W * self.length.capacity()
            + 4 * self.host.capacity()
    }
}

/// Lane `l` of a row's position, `ahead` of it along its velocity when `ahead` > 0.
#[inline(always)]
fn position_ahead(r: &StateRow, l: usize, ahead: f32) -> Vec3 {
    if ahead == 0.0 {
        r.x.get(l)
    } else {
        r.x.get(l) + ahead * r.v.get(l)
    }
}

/// The bridges as the block kernel reads them in a substep: the wet points' positions at its
/// start, their pairs, their point indices, each block's run of them.
pub struct Cohesion<'a> {
    xs: &'a [Vec3],
    pairs: &'a [Pairs],
    point: &'a [u32],
    block_start: &'a [u32],
    d_b: f32,
    ahead: f32,
}

impl Cohesion<'_> {
    /// Places of block `b`'s wet points.
    #[inline]
    pub fn block(&self, b: usize) -> std::ops::Range<usize> {
        self.block_start[b] as usize..self.block_start[b + 1] as usize
    }

    /// Adds to `f` (block `b`'s rows, from row `base`) the pull on each of its wet points:
    /// `c (1 - r / d_b) (x_j - x_i)` for `r < d_b`, summed in neighbour order (each pair's two
    /// pulls exact negatives), eight points at a time. Not inlined: in the block kernel it
    /// pushed the implicit solver's inner closures out of line, and out of its AVX2 build.
    #[inline(never)]
    pub fn pull_block(&self, b: usize, base: usize, avx2: bool, f: &mut [L3]) {
        let point = self.point;
        cohesion::pull_range(self.block(b), self.xs, self.pairs, self.d_b, avx2, |i, pull| {
            let p = point[i] as usize;
            let (r, l) = (p / W - base, p % W);
            f[r].x[l] += pull.x;
            f[r].y[l] += pull.y;
            f[r].z[l] += pull.z;
        });
    }

    /// Writes block `b`'s wet points' positions (after its substep) into `next`, this chunk's
    /// run starting at the place `first`.
    #[inline(always)]
    pub fn write_next(&self, b: usize, rows: &[StateRow], base: usize, first: usize, next: &mut [Vec3]) {
        for i in self.block(b) {
            let p = self.point[i] as usize;
            next[i - first] = position_ahead(&rows[p / W - base], p % W, self.ahead);
        }
    }

    /// The place of the first wet point of block `b` (a chunk's run of `next` starts there).
    #[inline]
    pub fn first_of(&self, b: usize) -> usize {
        self.block_start[b] as usize
    }
}

/// Writes each search's nearest into its point's record (`found[k]` is turn `k`'s), on the
/// pool: the turns are in index order, so each run of `CHUNK` of them writes a run of `near` of
/// its own. Written on one thread this was 10-12 ms a step on the soaked big groom.
fn record_found(
    near: &mut [Near],
    point: &[u32],
    turn: &[u32],
    found: &[([u32; MAX_BRIDGES], u8)],
    pool: Option<&Pool>,
) {
    let mut parts: Vec<(usize, &mut [Near])> = Vec::with_capacity(turn.len().div_ceil(CHUNK));
    let (mut rest, mut base) = (near, 0usize);
    for k0 in (0..turn.len()).step_by(CHUNK) {
        // This run's records end where the next run's first point's begins.
        let end = turn
            .get(k0 + CHUNK)
            .map_or(base + rest.len(), |&i| point[i as usize] as usize);
        let (mine, tail) = std::mem::take(&mut rest).split_at_mut(end - base);
        parts.push((base, mine));
        (rest, base) = (tail, end);
    }
    let write = |c: usize, (first, near): (usize, &mut [Near])| {
        let k0 = c * CHUNK;
        let k1 = (k0 + CHUNK).min(turn.len());
        for (&i, (q, n)) in turn[k0..k1].iter().zip(&found[k0..k1]) {
            let p = &mut near[point[i as usize] as usize - first];
            p.q = *q;
            p.n = *n as u16;
            p.searched = 1;
        }
    };
    match pool {
        Some(pool) => pool.install(|| parts.into_par_iter().enumerate().for_each(|(c, part)| write(c, part))),
        None => parts.into_iter().enumerate().for_each(|(c, part)| write(c, part)),
    }
}

/// How many wet points ahead the mutual test asks for their nearest's records: each point
/// reads up to six 32-byte records scattered over the groom's (51 MB on the big groom), and
/// waiting on each in turn was most of the test.
const PREFETCH_AHEAD: usize = 8;

/// Asks the cache for the records of the nearest of wet point `i` (nothing past the end).
#[inline(always)]
fn prefetch_nearest(near: &[Near], point: &[u32], i: usize) {
    if let Some(&p) = point.get(i) {
        let me = &near[p as usize];
        for &q in &me.q[..(me.n as usize).min(MAX_BRIDGES)] {
            prefetch::line(near.as_ptr().wrapping_add(q as usize));
        }
    }
}

/// What the pairs' coefficients read of a wet point.
#[derive(Debug, Clone, Copy, Default)]
struct WetTraits {
    /// Saturation, at most 1.
    sat: f32,
    /// Length of hair, m.
    len: f32,
    /// Inverse mass with its water, 1/kg (read here while the row is at hand: read by the
    /// mutual test, each was a cache miss).
    inv_mass: f32,
}

/// How many marked rows ahead the listing asks for their records.
const LIST_AHEAD: usize = 8;

/// What the listing reads of each row it lists from.
struct Sources<'a> {
    state: &'a [StateRow],
    held: &'a [[u32; W]],
    capacity: &'a [[u32; W]],
    params: &'a [ParamRow],
    length: &'a [Lane],
    host: &'a [u32],
}

impl Sources<'_> {
    /// Asks the cache for row `r`'s records, and its marked lanes' `near` records (`near`
    /// starts at the row's first).
    #[inline(always)]
    fn prefetch(&self, r: usize, near: &[Near], marks: u8) {
        prefetch::lines(std::slice::from_ref(&self.state[r].x));
        prefetch::line(&self.held[r]);
        prefetch::line(&self.capacity[r]);
        prefetch::line(&self.params[r].inv_mass);
        prefetch::line(&self.length[r]);
        prefetch::line(&self.host[r * W]);
        let mut m = marks;
        while m != 0 {
            prefetch::line(&near[m.trailing_zeros() as usize]);
            m &= m - 1;
        }
    }
}

/// A point's nearest wet points of other strands (point indices, sorted ascending, `n` of
/// them), whether it has searched since it became wet (1, else 0), and its place among this
/// step's wet points (`u32::MAX` when it is not wet): 32 bytes, so the mutual test reads each
/// point's in one cache line.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(32))]
struct Near {
    q: [u32; MAX_BRIDGES],
    n: u16,
    searched: u16,
    local: u32,
}

impl Near {
    const NONE: Near = Near {
        q: [0; MAX_BRIDGES],
        n: 0,
        searched: 0,
        local: u32::MAX,
    };
}

/// What a search reads of the wet points: by grid entry, the point index and strand; by point
/// index, the host point index.
struct Candidates<'a> {
    point: &'a [u32],
    strand: &'a [u32],
    host: &'a [u32],
}

/// The up to [`MAX_BRIDGES`] points nearest `x` within `reach` whose strand is not `own`,
/// nearest first with ties by host point index (a strict order, so the set does not depend on
/// the order the grid visits them, and both backends find the same), written to `out` as point
/// indices sorted ascending; returns how many.
fn nearest_of(grid: &HashGrid, x: Vec3, c: &Candidates, own: u32, reach: f32, out: &mut [u32; MAX_BRIDGES]) -> usize {
    let (point, strand, host) = (c.point, c.strand, c.host);
    // The few nearest so far, nearest first: squared distances, indices, count.
    let mut best = ([f32::INFINITY; MAX_BRIDGES], [0u32; MAX_BRIDGES], 0usize);
    let closer = |d: &[f32; MAX_BRIDGES], out: &[u32; MAX_BRIDGES], k: usize, d2: f32, q: u32| {
        d2 < d[k] || (d2 == d[k] && host[q as usize] < host[out[k] as usize])
    };
    // Once full, nothing farther than the last matters.
    let bound = |b: &([f32; MAX_BRIDGES], [u32; MAX_BRIDGES], usize)| b.0[MAX_BRIDGES - 1];
    grid.for_each_near_by(x, reach, &mut best, bound, |(d, out, n), j, d2| {
        // Farther than the few kept: most candidates in a clump end here, before the two
        // lookups below (a tie still needs the index).
        if *n == MAX_BRIDGES && d2 > d[MAX_BRIDGES - 1] {
            return;
        }
        if strand[j as usize] == own {
            return;
        }
        let q = point[j as usize];
        if *n == MAX_BRIDGES && !closer(d, out, MAX_BRIDGES - 1, d2, q) {
            return;
        }
        // Insertion into the sorted few: the farther ones move out by one.
        let mut k = (*n).min(MAX_BRIDGES - 1);
        while k > 0 && closer(d, out, k - 1, d2, q) {
            d[k] = d[k - 1];
            out[k] = out[k - 1];
            k -= 1;
        }
        d[k] = d2;
        out[k] = q;
        *n = (*n + 1).min(MAX_BRIDGES);
    });
    let n = best.2;
    out[..n].copy_from_slice(&best.1[..n]);
    out[..n].sort_unstable();
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{HeldWater, SimParams};

    /// The paper scene's 10,000 strands soaked at rest, dense enough that soaked points of
    /// different strands lie within the bridge length.
    struct Soaked {
        lay: Layout,
        held: super::super::held::Held,
        start: Vec<StateRow>,
        params: SimParams,
    }

    impl Soaked {
        fn new() -> Soaked {
            let groom = crate::groom::paper_scene(10_000, 6).unwrap();
            let params = SimParams {
                held_water: HeldWater::ON,
                ..SimParams::paper()
            };
            let lay = Layout::new(&groom, &params);
            let mut held = super::super::held::Held::new(&lay, params.held_water);
            held.soak(1.0);
            let start = lay.rest_state(&glam::Affine3A::IDENTITY);
            Soaked {
                lay,
                held,
                start,
                params,
            }
        }

        /// No pairs yet.
        fn bridges(&self) -> Bridges {
            let hw = &self.params.held_water;
            Bridges::new(&self.lay, hw.bridge_tension, hw.bridge_length_for(&self.params.water))
        }

        /// One step's search and pairs over the soaked rest state.
        fn step(&self, b: &mut Bridges) {
            let (lay, held) = (&self.lay, &self.held);
            b.find_pairs(
                lay,
                &self.start,
                &held.water,
                &held.capacity,
                &lay.params,
                1.0 / 240.0,
                true,
                false,
                None,
            );
        }
    }

    /// The positions the blocks write after a substep are the next substep's, and a block
    /// that does not run (a guide beyond a lowered simulated fraction) keeps the step's: every
    /// block's pulls then equal those packed afresh from the moved state, bit for bit.
    #[test]
    fn positions_written_by_the_blocks_are_the_next_substeps() {
        let soaked = Soaked::new();
        let (lay, start) = (&soaked.lay, &soaked.start);
        // As many steps as there are turns: every point has searched.
        let found = || {
            let mut b = soaked.bridges();
            for _ in 0..SEARCH_TURNS {
                soaked.step(&mut b);
            }
            b
        };
        let (mut blocks_wrote, mut truth) = (found(), found());
        assert!(blocks_wrote.active(), "the soaked scene bridges");
        // One substep: every block but the last chunk's moves and writes its positions.
        let (rows, chunk) = (lay.rows, 7);
        let active = lay.blocks - lay.blocks % chunk - chunk;
        let mut moved = start.clone();
        for (r, row) in moved.iter_mut().enumerate().take(active * rows) {
            for l in 0..W {
                row.x.x[l] += 1.0e-4 * ((r + l) % 7) as f32;
                row.x.z[l] -= 2.0e-4 * ((r * 3 + l) % 5) as f32;
            }
        }
        blocks_wrote.pack(start, 0.0, None);
        {
            let (c, mut next) = blocks_wrote.cohesion(chunk);
            for (k, part) in next.iter_mut().enumerate().take(active / chunk) {
                let first = k * chunk;
                for b in first..first + chunk {
                    c.write_next(b, &moved[b * rows..(b + 1) * rows], b * rows, c.first_of(first), part);
                }
            }
        }
        blocks_wrote.next_substep();
        truth.pack(&moved, 0.0, None);
        let (c, _) = blocks_wrote.cohesion(chunk);
        let (t, _) = truth.cohesion(chunk);
        let mut pulled = 0;
        for b in 0..lay.blocks {
            let (mut got, mut want) = (vec![L3::ZERO; rows], vec![L3::ZERO; rows]);
            c.pull_block(b, b * rows, false, &mut got);
            t.pull_block(b, b * rows, false, &mut want);
            let bits = |f: &[L3]| {
                f.iter()
                    .flat_map(|r| [r.x, r.y, r.z])
                    .flatten()
                    .map(f32::to_bits)
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&got), bits(&want), "block {b}");
            pulled += got.iter().any(|r| *r != L3::ZERO) as usize;
        }
        assert!(
            pulled > lay.blocks / 2,
            "most blocks are pulled ({pulled} of {})",
            lay.blocks
        );
    }

    /// A soaking wets every point at once, and each searches first on its turn: step k
    /// searches the points whose host index is k modulo the turns, and those that searched
    /// before and found no neighbour; after a round of turns every point has searched, and
    /// from then on a point with no neighbour searches every step.
    #[test]
    fn a_soaking_spreads_its_first_searches_over_the_turns() {
        let soaked = Soaked::new();
        let mut b = soaked.bridges();
        let mut lonely_searched = 0;
        for step in 0..2 * SEARCH_TURNS {
            // Who should search, from the records as the step finds them.
            let before: Vec<Near> = b.near.clone();
            soaked.step(&mut b);
            let wet = b.point.len();
            assert!(wet > 5_000, "the soaked groom's free points take part ({wet})");
            let expected: Vec<u32> = (0..wet as u32)
                .filter(|&i| {
                    let p = b.point[i as usize] as usize;
                    let on_turn = b.host[p] % SEARCH_TURNS == step % SEARCH_TURNS;
                    let lonely = before[p].searched != 0 && before[p].n == 0;
                    lonely_searched += (lonely && !on_turn) as usize;
                    on_turn || lonely
                })
                .collect();
            assert_eq!(b.turn, expected, "step {step}");
            // In the first round only points whose turn has come search: none at once.
            let had_turn = b
                .point
                .iter()
                .filter(|&&p| b.host[p as usize] % SEARCH_TURNS <= step)
                .count();
            assert!(b.turn.len() <= had_turn, "step {step}: {} searched", b.turn.len());
            if step == 0 {
                assert!(8 * b.turn.len() < 2 * wet, "{} of {wet} searched first", b.turn.len());
            }
            let searched = b.point.iter().filter(|&&p| b.near[p as usize].searched != 0).count();
            if step + 1 >= SEARCH_TURNS {
                assert_eq!(searched, wet, "step {step}: every point has searched");
            }
        }
        assert!(
            lonely_searched > 0,
            "points that found no neighbour searched again off their turn"
        );
        assert!(b.active(), "the soaked groom bridges");
    }
}
