//! Water particles on the CPU: storage, the hashed grid over them, their integration under
//! gravity, drag, the hair's reaction forces and colliders, and removal when they leave the
//! domain. Nothing here is allocated until the host first adds water.

use crate::error::{Error, Result};
use crate::params::WaterParams;
use crate::physics::adhesion::Reaction;
use crate::physics::collide::{collide_point, Placed};
use crate::physics::grid::Grid;
use crate::plan::{check_new_particles, WaterDomain};
use glam::{Affine3A, Vec3};

/// The particles and their grid.
#[derive(Debug)]
pub struct Water {
    /// Positions, world space, m.
    pub pos: Vec<Vec3>,
    /// Velocities, m/s.
    pub vel: Vec<Vec3>,
    /// Grid over `pos`, rebuilt every substep.
    pub grid: Grid,
    /// Positions in grid order (slot k is particle `grid.sorted()[k]`), coordinates apart.
    pub sorted: [Vec<f32>; 3],
    /// Force on each particle, in grid order (drag, then the hair's reactions).
    pub force: Vec<Vec3>,
    /// Domain centre in head space.
    pub center_local: Vec3,
    /// Domain radius, m.
    pub radius: f32,
    /// Particles removed for leaving the domain since creation (or reset).
    pub removed: u64,
}

impl Water {
    /// Allocates storage for `p.capacity` particles. The grid cell is `2 r_max`, so a query
    /// cube of side `2 r_max` overlaps exactly 8 cells.
    pub fn new(p: &WaterParams, domain: WaterDomain) -> Water {
        let cap = p.capacity as usize;
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
        }
    }

    /// Appends particles; `vel` may be empty (then at rest). Checks everything first, so a
    /// failed call adds nothing.
    pub fn add(&mut self, pos: &[Vec3], vel: &[Vec3], capacity: usize) -> Result<()> {
        check_new_particles(pos, vel)?;
        if self.pos.len() + pos.len() > capacity {
            return Err(Error::Capacity(format!(
                "{} particles held + {} added exceeds the water capacity {capacity}",
                self.pos.len(),
                pos.len()
            )));
        }
        self.pos.extend_from_slice(pos);
        if vel.is_empty() {
            self.vel.resize(self.pos.len(), Vec3::ZERO);
        } else {
            self.vel.extend_from_slice(vel);
        }
        Ok(())
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Pass `water_grid`: rebuilds the grid and copies positions into grid order.
    pub fn grid_build(&mut self) {
        self.grid.build(&self.pos);
        for (c, s) in self.sorted.iter_mut().enumerate() {
            s.clear();
            s.extend(self.grid.sorted().iter().map(|&j| self.pos[j as usize][c]));
        }
    }

    /// Pass `water_integrate`: symplectic Euler for every particle under its drag plus the
    /// hair's reactions, summed in the order given (block order, so the same bits for any
    /// thread count), then the colliders.
    pub fn integrate<'a>(
        &mut self,
        reactions: impl Iterator<Item = &'a [Reaction]>,
        p: &WaterParams,
        g: Vec3,
        h: f32,
        colliders: &[Placed],
        friction: f32,
    ) {
        let inv_m = 1.0 / p.particle_mass;
        self.force.clear();
        self.force
            .extend(self.grid.sorted().iter().map(|&j| -p.drag * self.vel[j as usize]));
        for r in reactions.flatten() {
            self.force[r.slot as usize] += Vec3::from(r.f);
        }
        for (k, &j) in self.grid.sorted().iter().enumerate() {
            let j = j as usize;
            let f = self.force[k];
            let v = self.vel[j] + h * (f * inv_m + g);
            let mut x = self.pos[j] + h * v;
            let mut v = v;
            for c in colliders {
                collide_point(&mut x, &mut v, c, friction);
            }
            self.pos[j] = x;
            self.vel[j] = v;
        }
    }

    /// Removes particles farther than the domain radius from the domain centre placed by
    /// `head` (swap-remove: order is not kept). Returns how many left.
    pub fn cull(&mut self, head: &Affine3A) -> usize {
        let c = head.transform_point3(self.center_local);
        let r2 = self.radius * self.radius;
        let before = self.pos.len();
        let mut j = 0;
        while j < self.pos.len() {
            if (self.pos[j] - c).length_squared() > r2 {
                self.pos.swap_remove(j);
                self.vel.swap_remove(j);
            } else {
                j += 1;
            }
        }
        let gone = before - self.pos.len();
        self.removed += gone as u64;
        gone
    }

    /// Removes every particle.
    pub fn clear(&mut self) {
        self.pos.clear();
        self.vel.clear();
    }
}
