//! The GPU backend behind the [`Engine`] seam.

use super::GpuBackend;
use crate::engine::{Counters, Engine, PointState};
use crate::error::Result;
use crate::params::{Backend, Integrator};
use crate::physics::followers::Followers;
use crate::physics::roots::RootFrame;
use crate::plan::Pass;
use glam::Quat;
use glam::{Affine3A, Vec3};

impl Engine for GpuBackend {
    fn kind(&self) -> Backend {
        Backend::GPU
    }

    fn integrator(&self) -> Integrator {
        GpuBackend::integrator(self)
    }

    fn passes(&self) -> Vec<Pass> {
        GpuBackend::passes(self)
    }

    fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        GpuBackend::add_water(self, pos, vel)
    }

    fn clear_water(&mut self) {
        GpuBackend::clear_water(self)
    }

    /// A failure seen by the last status read is reported before more work is submitted; the
    /// speed returned is that status's (the step just submitted has not run yet).
    fn particle_room(&self) -> usize {
        GpuBackend::particle_room(self)
    }

    fn set_wind(&mut self, wind: Vec3) {
        self.wind = wind;
    }

    fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<f32> {
        let last = self.last_status();
        self.check_status(&last)?;
        GpuBackend::step(self, dt, from, to)?;
        Ok(last.max_speed)
    }

    fn soak(&mut self, s: f32) -> Result<()> {
        GpuBackend::soak(self, s)
    }

    fn ledger(&self) -> Option<Result<crate::engine::WaterLedger>> {
        GpuBackend::ledger(self)
    }

    fn set_bundles(&mut self, bundle: &[f32], water: Option<&[u32]>) -> Result<()> {
        GpuBackend::set_bundles(self, bundle, water)
    }

    fn held_water(&self) -> Result<Vec<u32>> {
        GpuBackend::held_water(self)
    }

    fn set_substeps(&mut self, n: u32) {
        GpuBackend::set_substeps(self, n)
    }

    fn set_integrator(&mut self, integrator: Integrator) -> Result<()> {
        GpuBackend::set_integrator(self, integrator)
    }

    fn sample_every_step(&mut self, idx: &[u32]) -> bool {
        GpuBackend::sample_every_step(self, idx);
        true
    }

    fn sampled_behind(&mut self, out: &mut Vec<Vec3>) -> Result<bool> {
        GpuBackend::sampled_behind(self, out)
    }

    fn reset(&mut self, head: &Affine3A) {
        GpuBackend::reset(self, head)
    }

    fn place_sdfs(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()> {
        GpuBackend::place_sdfs(self, from, to);
        Ok(())
    }

    fn place_colliders(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()> {
        self.collider_frames.set(from, to);
        Ok(())
    }

    fn place_roots(&mut self, from: &[RootFrame], to: &[RootFrame]) -> Result<()> {
        GpuBackend::place_roots(self, from, to);
        Ok(())
    }

    fn carry_strands(&mut self, strands: &[u32], from: &[RootFrame], to: &[RootFrame]) -> Result<()> {
        GpuBackend::carry_strands(self, strands, from, to)
    }

    fn keep_previous(&mut self) -> Result<()> {
        GpuBackend::keep_previous(self)
    }

    fn blend_output(&mut self, a: Option<f32>) {
        GpuBackend::blend_output(self, a)
    }

    fn set_followers(&mut self, f: &Followers) -> Result<()> {
        GpuBackend::set_followers(self, f)
    }

    fn pose_followers(&mut self, head: Quat, blend: f32, roots: &[RootFrame]) {
        GpuBackend::pose_followers(self, head, blend, roots)
    }

    fn set_active_strands(&mut self, n: usize) {
        GpuBackend::set_active_strands(self, n)
    }

    fn seed_strands(&mut self, first: u32, x: &[Vec3], v: &[Vec3], wet: &[f32]) -> Result<()> {
        GpuBackend::seed_strands(self, first, x, v, wet)
    }

    /// The output pass writes the attributes fixed at create; this copies its floats.
    fn write_vertices(&mut self, dst: &mut [f32]) -> Result<()> {
        self.read_vertices(dst).map(|_| ())
    }

    fn point_states(&self) -> Result<Vec<PointState>> {
        Ok(self
            .read_state()?
            .into_iter()
            .map(|p| (Vec3::from_slice(&p.x), Vec3::from_slice(&p.v), p.x[3]))
            .collect())
    }

    fn water(&self) -> Result<(Vec<Vec3>, Vec<Vec3>)> {
        Ok(self
            .read_water()?
            .iter()
            .map(|p| (Vec3::from_slice(&p.x), Vec3::from_slice(&p.v)))
            .unzip())
    }

    /// Reads the status of the last step (waits for it); zeros if the device failed.
    fn counters(&self) -> Counters {
        let (st, removed) = self.peek_status().unwrap_or_default();
        Counters {
            particles: st.particles,
            particles_removed: removed,
            threads: 0,
            adhesion_pairs: 0,
        }
    }

    fn buffers(&self) -> Vec<(&'static str, usize)> {
        GpuBackend::buffers(self)
    }

    fn gpu_dispatches(&self) -> Vec<&'static str> {
        self.dispatches()
    }

    fn lose_device(&self) {
        GpuBackend::lose_device(self)
    }

    fn device_failure(&self) -> Option<crate::error::Error> {
        self.dev.check().err()
    }

    fn time_passes(&mut self, on: bool) -> bool {
        GpuBackend::time_passes(self, on)
    }

    fn pass_times(&self) -> Vec<crate::engine::PassTime> {
        GpuBackend::pass_times(self)
    }

    fn enable_gpu_timing(&mut self) -> bool {
        self.enable_timing()
    }

    fn last_step_gpu_ms(&self) -> Option<Result<f64>> {
        GpuBackend::last_step_gpu_ms(self)
    }

    fn gpu_grid(&mut self) -> Option<Result<crate::engine::GpuGrid>> {
        Some(self.read_grid())
    }

    fn bridge_searches(&mut self) -> Option<Result<u32>> {
        self.bridges.as_ref().map(|b| {
            let bytes = self.read_ranges(&[(b.bucket(), 4 * b.searches_word(), 4)], None)?;
            Ok(u32::from_le_bytes(bytes[..4].try_into().unwrap()))
        })
    }

    #[cfg(feature = "vulkan")]
    fn shared_frame(&mut self) -> Result<crate::gpu::vulkan::SharedFrame> {
        GpuBackend::shared_frame(self)
    }

    #[cfg(feature = "vulkan")]
    fn shared_water(&mut self) -> Result<crate::gpu::vulkan::SharedWater> {
        GpuBackend::shared_water(self)
    }
}
