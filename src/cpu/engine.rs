//! The CPU backend behind the [`Engine`] seam: answers in the host's order from the
//! strand-major blocks.

use super::step::CpuBackend;
use crate::engine::{Counters, Engine, PassTime, PointState, WaterLedger};
use crate::error::Result;
use crate::params::{Backend, Integrator};
use crate::physics::followers::Followers;
use crate::physics::roots::RootFrame;
use crate::plan::Pass;
use glam::{Affine3A, Quat, Vec3};

impl Engine for CpuBackend {
    fn kind(&self) -> Backend {
        Backend::CPU
    }

    fn integrator(&self) -> Integrator {
        CpuBackend::integrator(self)
    }

    fn passes(&self) -> Vec<Pass> {
        CpuBackend::passes(self)
    }

    fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        CpuBackend::add_water(self, pos, vel)
    }

    fn clear_water(&mut self) {
        CpuBackend::clear_water(self)
    }

    fn bridge_searches(&mut self) -> Option<Result<u32>> {
        self.bridges.as_ref().map(|b| Ok(b.searched()))
    }

    fn particle_room(&self) -> usize {
        let held = self.water.as_ref().map_or(0, |w| w.len());
        (self.params().water.capacity as usize).saturating_sub(held)
    }

    fn set_wind(&mut self, wind: Vec3) {
        CpuBackend::set_wind(self, wind)
    }

    fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<f32> {
        CpuBackend::step(self, dt, from, to).map(|rep| rep.max_speed)
    }

    fn reset(&mut self, head: &Affine3A) {
        CpuBackend::reset(self, head)
    }

    fn set_substeps(&mut self, n: u32) {
        CpuBackend::set_substeps(self, n)
    }

    fn set_integrator(&mut self, integrator: Integrator) -> Result<()> {
        CpuBackend::set_integrator(self, integrator);
        Ok(())
    }

    fn positions_of(&self, idx: &[u32], out: &mut Vec<Vec3>) -> Result<()> {
        out.clear();
        out.extend(idx.iter().map(|&i| self.position_of(i as usize)));
        Ok(())
    }

    fn place_sdfs(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()> {
        CpuBackend::place_sdfs(self, from, to);
        Ok(())
    }

    fn place_colliders(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()> {
        self.collider_frames.set(from, to);
        Ok(())
    }

    fn place_roots(&mut self, from: &[RootFrame], to: &[RootFrame]) -> Result<()> {
        CpuBackend::place_roots(self, from, to);
        Ok(())
    }

    fn carry_strands(&mut self, strands: &[u32], from: &[RootFrame], to: &[RootFrame]) -> Result<()> {
        CpuBackend::carry_strands(self, strands, from, to);
        Ok(())
    }

    fn keep_previous(&mut self) -> Result<()> {
        CpuBackend::keep_previous(self);
        Ok(())
    }

    fn blend_output(&mut self, a: Option<f32>) {
        CpuBackend::blend_output(self, a)
    }

    fn set_followers(&mut self, f: &Followers) -> Result<()> {
        match &mut self.followers {
            // The rest pose, spans and order are fixed at create: only the bindings change.
            Some(c) => {
                c.data.follow.clone_from(&f.follow);
                c.data.from.clone_from(&f.from);
            }
            None => self.followers = Some(super::followers::CpuFollowers::new(f.clone())),
        }
        Ok(())
    }

    fn pose_followers(&mut self, head: Quat, blend: f32, roots: &[RootFrame]) {
        if let Some(c) = &mut self.followers {
            c.head = head;
            c.blend = blend;
            c.roots.clear();
            c.roots.extend_from_slice(roots);
        }
    }

    fn set_active_strands(&mut self, n: usize) {
        self.active_blocks = n.min(self.lay.strands).div_ceil(crate::physics::lanes::W);
    }

    fn seed_strands(&mut self, first: u32, x: &[Vec3], v: &[Vec3], wet: &[f32]) -> Result<()> {
        let lay = &self.lay;
        let mut k = 0;
        let mut s = first as usize;
        while k < x.len() {
            let (b, l) = lay.lane_of(s);
            for i in 0..lay.strand_points(s) {
                let r = &mut self.state[b * lay.rows + i];
                r.x.set(l, x[k]);
                r.v.set(l, v[k]);
                if let Some(w) = self.wet.get_mut(b * lay.rows + i) {
                    w[l] = wet[k];
                }
                k += 1;
            }
            s += 1;
        }
        if let Some(h) = &mut self.held {
            h.state_changed();
        }
        self.restart_bdf2();
        Ok(())
    }

    fn write_vertices(&mut self, dst: &mut [f32]) -> Result<()> {
        let t = self.clock.start();
        CpuBackend::write_vertices(self, dst);
        self.clock.stop(crate::timers::Stage::Vertices, t);
        Ok(())
    }

    fn time_passes(&mut self, on: bool) -> bool {
        self.clock.set(on);
        true
    }

    fn pass_times(&self) -> Vec<PassTime> {
        self.clock.times()
    }

    fn point_states(&self) -> Result<Vec<PointState>> {
        let lay = &self.lay;
        let mut out = Vec::with_capacity(lay.mass.len());
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            for i in 0..lay.strand_points(s) {
                let r = &self.state[b * lay.rows + i];
                let w = self.wet.get(b * lay.rows + i).map_or(0.0, |w| w[l]);
                out.push((r.x.get(l), r.v.get(l), w));
            }
        }
        Ok(out)
    }

    fn water(&self) -> Result<(Vec<Vec3>, Vec<Vec3>)> {
        Ok(self
            .water
            .as_ref()
            .map_or_else(Default::default, |w| (w.pos.clone(), w.vel.clone())))
    }

    fn counters(&self) -> Counters {
        Counters {
            particles: self.water.as_ref().map_or(0, |w| w.len()) as u32,
            particles_removed: self.water.as_ref().map_or(0, |w| w.removed),
            threads: self.threads() as u32,
            adhesion_pairs: self.adhesion_pairs,
        }
    }

    fn run_jobs(&self, jobs: &mut [Box<dyn FnMut() + Send + '_>]) {
        match &self.pool {
            Some(pool) => pool.install(|| {
                use rayon::prelude::*;
                jobs.par_iter_mut().with_max_len(1).for_each(|j| j())
            }),
            None => jobs.iter_mut().for_each(|j| j()),
        }
    }

    fn buffers(&self) -> Vec<(&'static str, usize)> {
        CpuBackend::buffers(self)
    }

    fn soak(&mut self, s: f32) -> Result<()> {
        CpuBackend::soak(self, s)
    }

    fn ledger(&self) -> Option<Result<WaterLedger>> {
        CpuBackend::ledger(self).map(Ok)
    }

    fn set_bundles(&mut self, bundle: &[f32], water: Option<&[u32]>) -> Result<()> {
        self.bundle = match bundle.is_empty() {
            true => Vec::new(),
            false => self.lay.strand_rows(bundle, 1.0),
        };
        if let Some(h) = &mut self.held {
            h.set_bundles(&self.lay, &self.bundle);
            if let Some(w) = water {
                h.set_water_of_points(&self.lay, w);
            }
        }
        Ok(())
    }

    fn held_water(&self) -> Result<Vec<u32>> {
        Ok(self.held.as_ref().map_or(Vec::new(), |h| h.water_of_points(&self.lay)))
    }
}
