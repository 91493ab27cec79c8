//! Water particles on the CPU: storage, the hashed grid over them, their integration under
//! gravity, drag, the hair's reaction forces and colliders, and removal when they leave the
//! domain. Nothing here is allocated until the host first adds water.

use super::kernel::Worker;
use super::piles::Piles;
use super::slot_spans::{for_each_in_range, SlotSpan};
use crate::error::{Error, Result};
use crate::params::WaterParams;
use crate::physics::absorb::Demand;
use crate::physics::adhesion::{Reaction, Strength};
use crate::physics::collide::Colliders;
use crate::physics::grid::Grid;
use crate::physics::integrate::particle_velocity;
use crate::physics::lanes::W;
use crate::physics::pull_limit::{particle_limit, slope_h2};
use crate::physics::wet;
use crate::plan::{check_new_particles, WaterDomain};
use glam::{Affine3A, Vec3, Vec4};

/// Particles a task of `water_integrate` moves (fewer, and the pass runs on the calling
/// thread alone).
const PARTICLES_PER_TASK: usize = 16_384;

/// Reactions (or absorption demands) above which their sums per particle are shared among
/// the pool's threads.
const REACTIONS_PER_TASK: usize = 65_536;

/// Each chunk's absorption demands with their blocks' spans, in block order.
fn demand_lists(workers: &[Worker]) -> impl Iterator<Item = (&[Demand], &[SlotSpan])> + Clone {
    workers.iter().map(|w| (&w.demands[..], &w.demand_spans[..]))
}

/// The particles and their grid.
#[derive(Debug)]
pub struct Water {
    /// Positions, world space, m.
    pub pos: Vec<Vec3>,
    /// Velocities, m/s.
    pub vel: Vec<Vec3>,
    /// Grid over `pos`, rebuilt every substep; each build moves the particles into its order
    /// (`pos`, `vel` and `mass` are permuted by `grid.sorted()`), so grid slot k is particle k
    /// until the next build.
    pub grid: Grid,
    /// Positions in grid order (slot k is particle k since the build), coordinates apart.
    pub sorted: [Vec<f32>; 3],
    /// Force on each particle, in grid order: the hair's reactions (its drag is taken as it
    /// moves) in `xyz`, and in `w` how stiffly they hold it (`Reaction::stiffness`, summed: its
    /// side of eq. 2's stability limit).
    pub force: Vec<Vec4>,
    /// Domain centre in head space.
    pub center_local: Vec3,
    /// Domain radius, m.
    pub radius: f32,
    /// Particles removed since creation (or reset): left the domain, or emptied by the hair.
    pub removed: u64,
    /// With held water: each particle's water, quanta (empty in the paper's model, where
    /// every particle weighs `particle_mass`).
    pub mass: Vec<u32>,
    /// `mass` as of the substep's grid build: what the pull and the particle's own motion are
    /// reckoned with this substep (absorption takes from `mass` only).
    pub sorted_mass: Vec<u32>,
    /// Scratch of the build's permutation.
    pub moved: (Vec<Vec3>, Vec<Vec3>, Vec<u32>),
    /// With held water: quanta given by the host, and quanta that left (culled outside the
    /// domain, or cleared by the host).
    pub added: u64,
    /// See `added`.
    pub left: u64,
    /// Scratch of the absorb pass, per grid slot: demands summed, then quanta given, and the
    /// point that asked for most (with what it asked).
    demand: Vec<u64>,
    given: Vec<u64>,
    best: Vec<(u32, u32)>,
    /// Drops that met in one cell, coalesced and pulling as one source
    /// (`WaterParams::pile_cell` > 0, the paper's model only: `cpu/piles.rs`).
    piles: Option<Piles>,
}

impl Water {
    /// Allocates storage for `p.capacity` particles (`massive`: each carries its own water,
    /// for held water; `coalesce`: drops that meet coalesce, `SimParams::coalesces`). The grid
    /// cell is `2 r_max`, so a query cube of side `2 r_max` overlaps exactly 8 cells.
    pub fn new(p: &WaterParams, domain: WaterDomain, massive: bool, coalesce: bool) -> Water {
        let cap = p.capacity as usize;
        let per = |n: usize| if massive { n } else { 0 };
        Water {
            pos: Vec::with_capacity(cap),
            vel: Vec::with_capacity(cap),
            grid: Grid::new(cap, p.r_max),
            sorted: [
                Vec::with_capacity(cap),
                Vec::with_capacity(cap),
                Vec::with_capacity(cap),
            ],
            force: Vec::with_capacity(cap),
            center_local: domain.center_local,
            radius: domain.radius,
            removed: 0,
            mass: Vec::with_capacity(per(cap)),
            sorted_mass: Vec::with_capacity(per(cap)),
            moved: (
                Vec::with_capacity(cap),
                Vec::with_capacity(cap),
                Vec::with_capacity(per(cap)),
            ),
            added: 0,
            left: 0,
            demand: Vec::with_capacity(per(cap)),
            given: Vec::with_capacity(per(cap)),
            best: Vec::with_capacity(per(cap)),
            piles: coalesce.then(|| Piles::new(p.pile_cell, cap)),
        }
    }

    /// Eq. 2's strength `s` of each grid slot this substep: `s`, or `s` times the drops of
    /// each source while piles are active.
    pub fn strength(&self, s: f32) -> Strength<'_> {
        Strength {
            s,
            drops: self.piles.as_ref().map_or(&[], |p| p.drops()),
        }
    }

    /// Bytes held by the coalescence's grouping (0 without it).
    pub fn piles_bytes(&self) -> usize {
        self.piles.as_ref().map_or(0, Piles::bytes)
    }

    /// The grid's slots this substep: the particles, or with active piles their sources.
    pub fn sources(&self) -> usize {
        match &self.piles {
            Some(p) if p.active() => p.sources(),
            _ => self.pos.len(),
        }
    }

    /// Coalesces the drops that met and groups them into sources for this step (a no-op
    /// without `pile_cell`): called once a step, before its first grid build.
    pub fn group_piles(&mut self) {
        if let Some(p) = &mut self.piles {
            p.group(&mut self.pos, &mut self.vel);
        }
    }

    /// Whether each particle carries its own water (held water is on).
    pub fn massive(&self) -> bool {
        self.mass.capacity() > 0
    }

    /// Appends particles; `vel` may be empty (then at rest); each holds `quanta` of water when
    /// massive. Checks everything first, so a failed call adds nothing.
    pub fn add(&mut self, pos: &[Vec3], vel: &[Vec3], capacity: usize, quanta: u32) -> Result<()> {
        check_new_particles(pos, vel)?;
        if self.pos.len() + pos.len() > capacity {
            return Err(Error::Capacity(format!(
                "{} particles held + {} added exceeds the water capacity {capacity}",
                self.pos.len(),
                pos.len()
            )));
        }
        self.forget_piles();
        self.pos.extend_from_slice(pos);
        if vel.is_empty() {
            self.vel.resize(self.pos.len(), Vec3::ZERO);
        } else {
            self.vel.extend_from_slice(vel);
        }
        if self.massive() {
            self.mass.resize(self.pos.len(), quanta);
            self.added += quanta as u64 * pos.len() as u64;
        }
        Ok(())
    }

    /// Adds one drop (a drip from the hair, docs/WET_MODEL.md §6) holding `quanta` taken from
    /// the hair; false, adding nothing, when the water is at capacity.
    pub fn add_drop(&mut self, x: Vec3, v: Vec3, quanta: u32, capacity: usize) -> bool {
        if self.pos.len() >= capacity {
            return false;
        }
        self.forget_piles();
        self.pos.push(x);
        self.vel.push(v);
        self.mass.push(quanta);
        true
    }

    /// Drops were added or removed: the step's grouping no longer holds.
    fn forget_piles(&mut self) {
        if let Some(p) = &mut self.piles {
            p.forget();
        }
    }

    /// Water in particles, quanta.
    pub fn water_quanta(&self) -> u64 {
        self.mass.iter().map(|&q| q as u64).sum()
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Pass `water_grid`: rebuilds the grid and moves the particles into its order. Kept in
    /// the order of the last build, the particles are nearly sorted already: this pass's
    /// gather and `integrate`'s sweep read memory in order instead of a cache miss per
    /// particle (at a million particles both took a tenth of a second a substep).
    /// The moves run in chunks on `pool` when there are more than [`PARTICLES_PER_TASK`]
    /// particles (a million: 24 of the pass's 62 ms a frame, moved on one thread).
    pub fn grid_build(&mut self, pool: Option<&super::pool::Pool>) {
        if let Some(piles) = self.piles.as_mut().filter(|p| p.active()) {
            piles.build(&mut self.pos, &mut self.vel, &mut self.grid, &mut self.sorted);
            return;
        }
        self.grid.build(&self.pos);
        let massive = self.massive();
        let n = self.pos.len();
        let pool = pool.filter(|_| n > PARTICLES_PER_TASK);
        let order = self.grid.sorted();
        let (pos, vel, mass) = &mut self.moved;
        pos.resize(n, Vec3::ZERO);
        vel.resize(n, Vec3::ZERO);
        let (from_pos, from_vel) = (&self.pos, &self.vel);
        super::pool::for_chunks2(pool, pos, vel, PARTICLES_PER_TASK, |first, p, v| {
            let order = &order[first..first + p.len()];
            for ((p, v), &j) in p.iter_mut().zip(v).zip(order) {
                (*p, *v) = (from_pos[j as usize], from_vel[j as usize]);
            }
        });
        std::mem::swap(pos, &mut self.pos);
        std::mem::swap(vel, &mut self.vel);
        if massive {
            mass.clear();
            mass.extend(order.iter().map(|&j| self.mass[j as usize]));
            std::mem::swap(mass, &mut self.mass);
            self.sorted_mass.clear();
            self.sorted_mass.extend_from_slice(&self.mass);
        }
        let [sx, sy, sz] = &mut self.sorted;
        for s in [&mut *sx, &mut *sy, &mut *sz] {
            s.resize(n, 0.0);
        }
        let at = &self.pos;
        let chunk = PARTICLES_PER_TASK;
        super::pool::for_chunks2(pool, sx, sy, chunk, |first, x, y| {
            for ((x, y), p) in x.iter_mut().zip(y).zip(&at[first..]) {
                (*x, *y) = (p.x, p.y);
            }
        });
        super::pool::for_chunks(pool, sz, chunk, |first, z| {
            for (z, p) in z.iter_mut().zip(&at[first..]) {
                *z = p.z;
            }
        });
    }

    /// Pass `absorb` (docs/WET_MODEL.md §2): grants the substep's demands, listed in block
    /// order, from the particles to the hair points (`held`, per row of lanes). Each particle
    /// gives every demand in full while they sum to at most its water, else its share rounded
    /// down; a point takes grants up to [`wet::HELD_LIMIT`] and the particle keeps what it
    /// refuses. A particle left with less than `last`
    /// quanta goes whole to the point that asked it for most (first found on a tie).
    /// Integers throughout: the particles lose exactly what the hair gains, whatever the order.
    ///
    /// With many demands the pool shares it: the sums per particle by ranges of particles
    /// (each task reading the blocks' runs that meet its range, in list order, so the largest
    /// asker on a tie is the same), the grants by chunks of blocks (a chunk's demands name
    /// only its own points, so each point takes its grants in the same order), then what each
    /// particle gave by ranges again. Each demand holds what it was granted afterwards.
    pub fn absorb(
        &mut self,
        workers: &mut [Worker],
        held: &mut [[u32; W]],
        chunk_rows: usize,
        last: u32,
        pool: Option<&super::pool::Pool>,
    ) {
        let n = self.sorted_mass.len();
        self.demand.clear();
        self.demand.resize(n, 0);
        self.given.clear();
        self.given.resize(n, 0);
        self.best.clear();
        self.best.resize(n, (0, 0));
        let total: usize = workers.iter().map(|w| w.demands.len()).sum();
        let tasks = pool.map_or(1, |p| p.threads());
        let shared = pool.filter(|_| total > REACTIONS_PER_TASK && n > tasks);
        let size = n.div_ceil(tasks).max(1);
        {
            let workers = &*workers;
            super::pool::for_chunks2(shared, &mut self.demand, &mut self.best, size, |first, demand, best| {
                let range = first as u32..(first + demand.len()) as u32;
                for_each_in_range(
                    demand_lists(workers),
                    range,
                    |d| d.slot,
                    |d| {
                        let k = d.slot as usize - first;
                        demand[k] += d.quanta as u64;
                        if d.quanta > best[k].1 {
                            best[k] = (d.point, d.quanta);
                        }
                    },
                );
            });
        }
        // A point takes a grant up to its room below its hold limit at the substep's start, and
        // in all up to `HELD_LIMIT` (what it refuses stays in the particle).
        let (mass, demand) = (&self.sorted_mass, &self.demand);
        let grants = |k: usize, w: &mut Worker, held: &mut [[u32; W]]| {
            let first_point = k * chunk_rows * W;
            for d in &mut w.demands {
                let g = wet::grant(mass[d.slot as usize], d.quanta, demand[d.slot as usize]).min(d.room);
                let p = d.point as usize - first_point;
                let (r, l) = (p / W, p % W);
                let q = g.min(wet::HELD_LIMIT.saturating_sub(held[r][l]));
                held[r][l] += q;
                d.quanta = q;
            }
        };
        match shared {
            Some(pool) => pool.install(|| {
                use rayon::prelude::*;
                workers
                    .par_iter_mut()
                    .zip(held.par_chunks_mut(chunk_rows))
                    .enumerate()
                    .for_each(|(k, (w, h))| grants(k, w, h))
            }),
            None => {
                for (k, (w, h)) in workers.iter_mut().zip(held.chunks_mut(chunk_rows)).enumerate() {
                    grants(k, w, h);
                }
            }
        }
        {
            let workers = &*workers;
            super::pool::for_chunks(shared, &mut self.given, size, |first, given| {
                let range = first as u32..(first + given.len()) as u32;
                for_each_in_range(
                    demand_lists(workers),
                    range,
                    |d| d.slot,
                    |d| {
                        given[d.slot as usize - first] += d.quanta as u64;
                    },
                );
            });
        }
        // Remainders are small (under a thousandth of a particle each), so they are not held
        // to the limit; only the count's own end bounds them.
        for k in 0..n {
            let left = self.sorted_mass[k] - self.given[k] as u32;
            let (point, asked) = self.best[k];
            if asked > 0 && left > 0 && left < last {
                let (r, l) = (point as usize / W, point as usize % W);
                let q = left.min(u32::MAX - held[r][l]);
                held[r][l] += q;
                self.given[k] += q as u64;
            }
        }
        // `sorted_mass` keeps the water the substep's pull was reckoned with: the particle
        // moves under that pull with that mass (`integrate`).
        for (m, &g) in self.mass.iter_mut().zip(&self.given) {
            *m -= g as u32; // at most the particle's own count
        }
    }

    /// Pass `water_integrate`: symplectic Euler for every particle under the hair's reactions,
    /// summed in the order given (block order, so the same bits for any thread count), with its
    /// drag taken implicitly (`integrate::particle_velocity`), then the colliders. Each list of
    /// reactions comes with its spans, which cover it in order.
    #[allow(clippy::too_many_arguments)]
    pub fn integrate<'a>(
        &mut self,
        reactions: impl Iterator<Item = (&'a [Reaction], &'a [SlotSpan])> + Clone + Sync,
        p: &WaterParams,
        g: Vec3,
        wind: Vec3,
        h: f32,
        colliders: Colliders,
        friction: f32,
        pool: Option<&super::pool::Pool>,
    ) {
        let inv_m0 = 1.0 / p.particle_mass;
        // A particle's drag scales with its water, so every drop, whatever its size, slows at
        // the rate a full particle does (`drag / particle_mass`) and falls alike; it is taken
        // implicitly as the particle moves (`integrate::particle_velocity`).
        let drag_rate = p.drag * inv_m0;
        let (slope_h2, per_mass) = (slope_h2(h, p.r_min, p.r_max), p.adhesion * inv_m0);
        self.force.clear();
        // One sum per grid slot: a particle, or with piles a source.
        self.force.resize(self.sources(), Vec4::ZERO);
        // Each particle sums its reactions in the order given. With many, each task takes a
        // range of particles and reads the blocks' runs of reactions that touch it, keeping its
        // own: the sums are the same, and the scattered adds are shared (a million drops: most
        // of the pass's 117 ms a frame, summed on one thread). Reading every run in every task
        // made each read all the reactions: 30 million a substep on the big groom at a million
        // drops, 95 ms, most of the pass.
        let total: usize = reactions.clone().map(|(r, _)| r.len()).sum();
        let n = self.force.len();
        let tasks = pool.map_or(1, |p| p.threads());
        let pool_sum = pool.filter(|_| total > REACTIONS_PER_TASK && n > tasks);
        super::pool::for_chunks(pool_sum, &mut self.force, n.div_ceil(tasks), |first, force| {
            let range = first as u32..(first + force.len()) as u32;
            let start = range.start;
            for_each_in_range(
                reactions.clone(),
                range,
                |r| r.slot,
                |r| {
                    force[(r.slot - start) as usize] += Vec3::from(r.f).extend(r.stiffness);
                },
            );
        });
        // With piles, each drop takes its share of its source's.
        let force = match self.piles.as_mut().filter(|p| p.active()) {
            Some(piles) => piles.share(&self.force),
            None => &self.force,
        };
        // Each particle then moves on its own: in chunks on the pool.
        let mass = &self.sorted_mass;
        let chunk = PARTICLES_PER_TASK;
        let pool = pool.filter(|_| self.pos.len() > chunk);
        super::pool::for_chunks2(pool, &mut self.pos, &mut self.vel, chunk, |first, pos, vel| {
            for (k, (x, v)) in pos.iter_mut().zip(vel.iter_mut()).enumerate() {
                let j = first + k;
                // A held-water particle weighs the water it held when the hair's pull on it
                // was reckoned, at the substep's start (what the hair drank since leaves with
                // the momentum it had: dividing that pull by the little left flung drained
                // drops out at kilometres per second); an empty one (removed at the end of
                // the step) only falls.
                let inv_m = match mass.get(j) {
                    None => inv_m0,
                    Some(0) => 0.0,
                    Some(&q) => (1.0 / wet::to_kg(q)) as f32,
                };
                let rate = if inv_m > 0.0 { drag_rate } else { 0.0 };
                // Its side of eq. 2's stability limit: held by more hair than a substep
                // follows, it responds to its forces more slowly, its drag damping it at its
                // own rate (`pull_limit::particle_limit`).
                let f = force[j];
                let factor = if inv_m > 0.0 {
                    particle_limit(slope_h2, per_mass, f.w)
                } else {
                    1.0
                };
                let a = factor * (f.truncate() * inv_m + g);
                *v = particle_velocity(*v, a, rate, factor * wind, h);
                *x += h * *v;
                colliders.push_out_point(x, v, friction);
            }
        });
    }

    /// Removes particles farther than the domain radius from the domain centre placed by
    /// `head` (their water is booked as left), and with held water the particles the hair
    /// emptied (swap-remove: order is not kept). Returns how many went.
    pub fn cull(&mut self, head: &Affine3A) -> usize {
        let c = head.transform_point3(self.center_local);
        let r2 = self.radius * self.radius;
        let before = self.pos.len();
        self.forget_piles();
        let massive = self.massive();
        let mut j = 0;
        while j < self.pos.len() {
            let outside = (self.pos[j] - c).length_squared() > r2;
            let empty = massive && self.mass[j] == 0;
            if outside || empty {
                self.pos.swap_remove(j);
                self.vel.swap_remove(j);
                if massive {
                    self.left += self.mass.swap_remove(j) as u64;
                }
            } else {
                j += 1;
            }
        }
        let gone = before - self.pos.len();
        self.removed += gone as u64;
        gone
    }

    /// Removes every particle (its water is booked as left).
    pub fn clear(&mut self) {
        self.forget_piles();
        self.pos.clear();
        self.vel.clear();
        self.left += self.water_quanta();
        self.mass.clear();
    }

    /// Removes every particle and empties the ledger.
    pub fn reset(&mut self) {
        self.clear();
        self.removed = 0;
        self.added = 0;
        self.left = 0;
    }
}
