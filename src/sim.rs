//! [`Simulation`]: the Rust API every front end (C ABI, examples, tests) goes through.

use crate::cpu::step::{CpuBackend, Pass};
use crate::error::{invalid, Error, Result};
use crate::groom::Groom;
use crate::params::{SimParams, VertexAttributes};
use crate::physics::clumping::mean_nearest_tip_distance;
use crate::physics::spring::spring_energy;
use glam::{Affine3A, DVec3, Mat4, Vec3};
use std::time::Instant;

/// Longest time step `step` accepts, s.
pub const MAX_DT: f32 = 1.0;

/// Counters and measures of a simulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Strands.
    pub strands: u32,
    /// Hair points (all strands).
    pub points: u32,
    /// Water particles now.
    pub particles: u32,
    /// Water particles removed for leaving the domain since create or reset.
    pub particles_removed: u64,
    /// Steps taken since create or reset.
    pub steps: u64,
    /// Wall time of the last step, ms.
    pub last_step_ms: f32,
    /// Largest point speed in the last step, m/s.
    pub max_speed: f32,
    /// Mean distance from each strand tip to the nearest other tip, m (drops as hair clumps).
    pub clumping: f32,
    /// Worker threads.
    pub threads: u32,
    /// The integrator in use (`Auto` resolved).
    pub integrator: crate::Integrator,
}

/// Energies of the hair and water, J (diagnostics and tests).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Kinetic energy of free hair points and water particles.
    pub kinetic: f64,
    /// Potential energy stored in stretch and bend springs.
    pub spring: f64,
    /// Gravitational potential of free hair points and particles, relative to the origin.
    pub gravity: f64,
}

impl Energy {
    /// The sum of all terms.
    pub fn total(&self) -> f64 {
        self.kinetic + self.spring + self.gravity
    }
}

/// One wet-hair simulation: a groom, its parameters, the head transform, and water.
///
/// Not thread-safe: calls on one simulation must not overlap (the C ABI documents the same).
/// The step itself runs on the simulation's own worker threads.
#[derive(Debug)]
pub struct Simulation {
    params: SimParams,
    cpu: CpuBackend,
    head: Affine3A,
    head_prev: Affine3A,
    last_step_ms: f32,
    max_speed: f32,
    steps: u64,
    failed: Option<Error>,
}

impl Simulation {
    /// Validates `params` and lays out `groom` (copied; the groom may be dropped after).
    pub fn new(groom: &Groom, params: SimParams) -> Result<Self> {
        params.validate()?;
        let head = Affine3A::IDENTITY;
        let cpu = CpuBackend::new(groom, &params, &head)?;
        Ok(Simulation {
            params,
            cpu,
            head,
            head_prev: head,
            last_step_ms: 0.0,
            max_speed: 0.0,
            steps: 0,
            failed: None,
        })
    }

    /// The parameters the simulation was created with.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// Sets where the head is at the end of the next step (column-major 4×4, affine, no
    /// reflection). Pinned points and colliders move from the previous transform to this one
    /// over the step's substeps.
    pub fn set_head_transform(&mut self, m: Mat4) -> Result<()> {
        let a = m.to_cols_array();
        if a.iter().any(|v| !v.is_finite()) {
            return Err(invalid!("head transform has a non-finite entry"));
        }
        let row3 = m.row(3);
        if (row3 - glam::Vec4::W).abs().max_element() > 1e-5 {
            return Err(invalid!("head transform's last row must be (0, 0, 0, 1), got {row3:?}"));
        }
        let t = Affine3A::from_mat4(m);
        let det = t.matrix3.determinant();
        if det.is_nan() || det <= 1e-12 {
            return Err(invalid!("head transform is singular or mirrored (determinant {det})"));
        }
        self.head = t;
        Ok(())
    }

    /// Adds water particles at `pos` with velocities `vel` (empty: at rest).
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        self.cpu.add_water(pos, vel)
    }

    /// Removes every water particle (hair stays as wet as it is).
    pub fn clear_water(&mut self) {
        self.cpu.clear_water();
    }

    /// Advances the simulation by `dt` seconds (0 < dt <= 1).
    ///
    /// A step that produces a non-finite value returns [`Error::Unstable`] and marks the
    /// simulation failed: further steps and vertex reads return the same error until
    /// [`Simulation::reset`].
    pub fn step(&mut self, dt: f32) -> Result<()> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if !(dt.is_finite() && dt > 0.0 && dt <= MAX_DT) {
            return Err(invalid!("dt must be finite, > 0 and <= {MAX_DT} s, got {dt}"));
        }
        let t0 = Instant::now();
        let r = self.cpu.step(dt, &self.head_prev, &self.head);
        self.last_step_ms = t0.elapsed().as_secs_f32() * 1e3;
        self.head_prev = self.head;
        self.steps += 1;
        match r {
            Ok(rep) => {
                self.max_speed = rep.max_speed;
                Ok(())
            }
            Err(e) => {
                self.failed = Some(e.clone());
                Err(e)
            }
        }
    }

    /// Back to the rest pose at the current head transform: zero velocity, dry, no water,
    /// counters cleared, failure forgotten.
    pub fn reset(&mut self) {
        self.cpu.reset(&self.head);
        self.head_prev = self.head;
        self.failed = None;
        self.steps = 0;
        self.max_speed = 0.0;
    }

    /// Whether a step failed and the simulation waits for a reset.
    pub fn failed(&self) -> Option<&Error> {
        self.failed.as_ref()
    }

    /// Hair points written per [`Simulation::write_vertices`].
    pub fn vertex_count(&self) -> usize {
        self.cpu.lay.mass.len()
    }

    /// Strand and point counts.
    pub fn stats_counts(&self) -> (u32, u32) {
        (self.cpu.lay.strands as u32, self.vertex_count() as u32)
    }

    /// The attributes written per vertex.
    pub fn attributes(&self) -> VertexAttributes {
        self.params.attributes
    }

    /// Writes the requested attributes of every point, interleaved, strand after strand.
    /// `dst` must hold at least `vertex_count() * stride` floats; returns the floats written.
    /// Writes nothing on error.
    pub fn write_vertices(&self, dst: &mut [f32]) -> Result<usize> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let n = self.vertex_count() * self.params.attributes.stride();
        if dst.len() < n {
            return Err(Error::Capacity(format!(
                "vertex buffer holds {} floats, {n} needed",
                dst.len()
            )));
        }
        self.cpu.write_vertices(self.params.attributes, &mut dst[..n]);
        Ok(n)
    }

    /// The passes the next step will run (only those the scene needs).
    pub fn passes(&self) -> Vec<Pass> {
        self.cpu.passes()
    }

    /// Every buffer the simulation holds and its size in bytes.
    pub fn buffers(&self) -> Vec<(&'static str, usize)> {
        self.cpu.buffers()
    }

    /// Every point's position, strand after strand.
    pub fn positions(&self) -> Vec<Vec3> {
        self.per_point(|r, l| r.x.get(l))
    }

    /// Every point's velocity, strand after strand.
    pub fn velocities(&self) -> Vec<Vec3> {
        self.per_point(|r, l| r.v.get(l))
    }

    fn per_point<T>(&self, f: impl Fn(&crate::cpu::layout::StateRow, usize) -> T) -> Vec<T> {
        let lay = &self.cpu.lay;
        let mut out = Vec::with_capacity(self.vertex_count());
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            for i in 0..lay.strand_points(s) {
                out.push(f(&self.cpu.state[b * lay.rows + i], l));
            }
        }
        out
    }

    /// Water particle positions (order changes when particles are removed).
    pub fn water_positions(&self) -> &[Vec3] {
        self.cpu.water.as_ref().map_or(&[], |w| &w.pos)
    }

    /// Water particle velocities, in the order of [`Simulation::water_positions`].
    pub fn water_velocities(&self) -> &[Vec3] {
        self.cpu.water.as_ref().map_or(&[], |w| &w.vel)
    }

    /// Tip positions of every strand, in host order.
    pub fn tips(&self) -> Vec<Vec3> {
        let lay = &self.cpu.lay;
        (0..lay.strands)
            .map(|s| {
                let (b, l) = lay.lane_of(s);
                self.cpu.state[b * lay.rows + lay.strand_points(s) - 1].x.get(l)
            })
            .collect()
    }

    /// Counters and measures (the clumping measure is computed now, O(strands)).
    pub fn stats(&self) -> Stats {
        let lay = &self.cpu.lay;
        Stats {
            strands: lay.strands as u32,
            points: self.vertex_count() as u32,
            particles: self.water_positions().len() as u32,
            particles_removed: self.cpu.water.as_ref().map_or(0, |w| w.removed),
            steps: self.steps,
            last_step_ms: self.last_step_ms,
            max_speed: self.max_speed,
            clumping: mean_nearest_tip_distance(&self.tips()),
            threads: self.cpu.threads() as u32,
            integrator: self.cpu.integrator(),
        }
    }

    /// Total linear momentum of free hair points and water particles, kg·m/s.
    pub fn momentum(&self) -> DVec3 {
        let pinned = self.pinned_mask();
        let hair: DVec3 = self
            .velocities()
            .iter()
            .zip(&self.cpu.lay.mass)
            .zip(&pinned)
            .filter(|(_, &p)| !p)
            .map(|((v, &m), _)| v.as_dvec3() * m as f64)
            .sum();
        let m_w = self.params.water.particle_mass as f64;
        hair + self
            .water_velocities()
            .iter()
            .map(|v| v.as_dvec3() * m_w)
            .sum::<DVec3>()
    }

    fn pinned_mask(&self) -> Vec<bool> {
        let lay = &self.cpu.lay;
        let mut out = Vec::with_capacity(self.vertex_count());
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            for i in 0..lay.strand_points(s) {
                out.push(lay.params[b * lay.rows + i].inv_mass[l] == 0.0);
            }
        }
        out
    }

    /// Kinetic, spring and gravitational energy (f64 sums).
    pub fn energy(&self) -> Energy {
        let lay = &self.cpu.lay;
        let g = self.params.gravity.as_dvec3();
        let mut e = Energy::default();
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let n = lay.strand_points(s);
            let first = lay.strand_first[s] as usize;
            for i in 0..n {
                let r = &self.cpu.state[b * lay.rows + i];
                let prm = &lay.params[b * lay.rows + i];
                if prm.inv_mass[l] > 0.0 {
                    let m = lay.mass[first + i] as f64;
                    e.kinetic += 0.5 * m * r.v.get(l).as_dvec3().length_squared();
                    e.gravity -= m * g.dot(r.x.get(l).as_dvec3());
                }
                if i + 1 < n {
                    let len = (self.cpu.state[b * lay.rows + i + 1].x.get(l) - r.x.get(l)).length();
                    e.spring += spring_energy(prm.stretch.k[l], prm.stretch.rest[l], len);
                }
                if i + 2 < n {
                    let len = (self.cpu.state[b * lay.rows + i + 2].x.get(l) - r.x.get(l)).length();
                    e.spring += spring_energy(prm.bend.k[l], prm.bend.rest[l], len);
                }
            }
        }
        let m_w = self.params.water.particle_mass as f64;
        for (x, v) in self.water_positions().iter().zip(self.water_velocities()) {
            e.kinetic += 0.5 * m_w * v.as_dvec3().length_squared();
            e.gravity -= m_w * g.dot(x.as_dvec3());
        }
        e
    }
}
