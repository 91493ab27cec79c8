//! Water on the GPU: the particle, grid and reaction buffers and their pipelines (made at the
//! first `add_water`), pass water_grid's encoding, adding and clearing particles, and the
//! blocking reads tests use (particles, the grid: counts and mark table).

use super::super::buffers::{
    self as b, grid_header as gh, groups, ParticleGpu, GRID_COUNT_HEADER, STORAGE, WATER_FORCE_WORDS,
};
use super::super::pipelines::{self as pl, Slot};
use super::kernels::HairKernels;
use super::piles::PilesGpu;
use super::reactions::ReactionsGpu;
use super::GpuBackend;
use crate::error::{Error, Result};
use crate::physics::hash_grid::buckets_for;
use crate::plan::{check_new_particles, pass_list};
use glam::Vec3;

/// Water buffers and pipelines, created at the first `add_water`.
#[derive(Debug)]
pub(super) struct WaterGpu {
    pub(super) particles: [wgpu::Buffer; 2],
    /// The particles' reaction sums (`buffers::WATER_FORCE_WORDS` words each); where the
    /// particles gather them, also the points' records (`buffers::wet_words`).
    pub(super) force: wgpu::Buffer,
    pub(super) grid_count: wgpu::Buffer,
    pub(super) grid: wgpu::Buffer,
    pub(super) state: wgpu::Buffer,
    pub(super) dispatch: wgpu::Buffer,
    pub(super) incoming: wgpu::Buffer,
    /// Absorption's per-particle scratch in grid order (`buffers::absorb_words`).
    pub(super) absorb: wgpu::Buffer,
    /// Build bind groups: [cur = A, other = B], [cur = B, other = A].
    pub(super) build_bg: [wgpu::BindGroup; 2],
    /// The indirect-dispatch buffer as storage (grid_setup only).
    pub(super) dispatch_bg: wgpu::BindGroup,
    /// Hair-side bind groups: sorted = B (when cur = A), sorted = A.
    pub(super) hair_bg: [wgpu::BindGroup; 2],
    /// Pipelines by entry point (see `WATER_ENTRIES`).
    pub(super) pipes: Vec<wgpu::ComputePipeline>,
    /// The hair kernels of the wet scene.
    pub(super) wet_hair: HairKernels,
    /// The water group's layout in the hair kernels (to rebuild them for another integrator).
    pub(super) hair_layout: wgpu::BindGroupLayout,
    /// Which particle buffer holds the particles.
    pub(super) cur: usize,
    /// An upper bound on the particles held (exact after a status read).
    pub(super) bound: u32,
    /// Particles uploaded, waiting for the next step's append.
    pub(super) pending: u32,
    /// Removed since create or reset, as of the last status read.
    pub(super) removed: u64,
    /// Drops that meet coalesce (`SimParams::coalesces`): their grouping.
    pub(super) piles: Option<PilesGpu>,
    /// The particles gather their reactions (`SceneConsts::gathered`): its passes.
    pub(super) reactions: Option<ReactionsGpu>,
}

pub(super) const WATER_ENTRIES: [&str; 10] = [
    "water_append",
    "grid_bounds",
    "grid_setup",
    "grid_count_cells",
    "grid_scan_blocks",
    "grid_scan_sums",
    "grid_scan_add",
    "grid_scatter",
    "water_cull",
    "water_cull_finish",
];

impl WaterGpu {
    /// Encodes pass water_grid over the held particles: bounds, setup, count, prefix sum and,
    /// with `scatter`, the scatter into grid order (without it the counts stay for a test).
    pub(super) fn encode_grid(&self, pass: &mut wgpu::ComputePass, scatter: bool) {
        let (gx, gy) = groups(self.bound.max(1));
        pass.set_bind_group(0, &self.build_bg[self.cur], &[]);
        let last = if scatter { 8 } else { 7 };
        for (k, p) in self.pipes[1..last].iter().enumerate() {
            pass.set_pipeline(p);
            match WATER_ENTRIES[k + 1] {
                "grid_setup" => {
                    pass.set_bind_group(1, &self.dispatch_bg, &[]);
                    pass.dispatch_workgroups(1, 1, 1)
                }
                "grid_scan_sums" => pass.dispatch_workgroups(1, 1, 1),
                "grid_scan_blocks" | "grid_scan_add" => pass.dispatch_workgroups_indirect(&self.dispatch, 0),
                _ => pass.dispatch_workgroups(gx, gy, 1),
            }
        }
    }
}

impl GpuBackend {
    /// Room for particles as far as the host knows without reading the device: the capacity
    /// less the upper bound on those held and those waiting.
    pub fn particle_room(&self) -> usize {
        let cap = self.params.water.capacity;
        self.water
            .as_ref()
            .map_or(cap, |w| cap.saturating_sub(w.bound + w.pending)) as usize
    }

    /// Uploads particles (they join at the next step); water buffers are created at the
    /// first call.
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        check_new_particles(pos, vel)?;
        if pos.is_empty() {
            return Ok(());
        }
        let cap = self.params.water.capacity;
        if self.water.is_none() {
            if pos.len() > cap as usize {
                return Err(Error::Capacity(format!(
                    "{} particles exceed the water capacity {cap}",
                    pos.len()
                )));
            }
            self.water = Some(self.create_water()?);
        }
        let n = pos.len() as u32;
        let w = self.water.as_ref().expect("created above");
        if w.bound + w.pending + n > cap {
            // The bound may be stale after culls: read the exact count first.
            self.read_status()?;
        }
        let w = self.water.as_mut().expect("created above");
        if w.bound + w.pending + n > cap {
            return Err(Error::Capacity(format!(
                "{} particles held + {} waiting + {n} added exceeds the water capacity {cap}",
                w.bound, w.pending
            )));
        }
        // With held water each particle carries `particle_mass` of water, in quanta.
        let mass = if self.params.held_water.enabled {
            crate::physics::wet::to_quanta(self.params.water.particle_mass as f64)
        } else {
            0
        };
        let recs: Vec<ParticleGpu> = pos
            .iter()
            .enumerate()
            .map(|(i, p)| ParticleGpu {
                x: p.to_array(),
                mass,
                v: vel.get(i).copied().unwrap_or(Vec3::ZERO).to_array(),
                left: 0,
            })
            .collect();
        self.dev
            .queue
            .write_buffer(&w.incoming, w.pending as u64 * 32, bytemuck::cast_slice(&recs));
        w.pending += n;
        self.particles_added += n as u64;
        Ok(())
    }

    /// Removes every particle (with held water, their water is booked as left).
    pub fn clear_water(&mut self) {
        if self.held.is_some() && self.water.is_some() {
            // A blocking read, as the host rarely clears: what the particles carried leaves.
            let q = crate::physics::wet::to_quanta(self.params.water.particle_mass as f64) as u64;
            let pending = self.water.as_ref().map_or(0, |w| w.pending as u64);
            self.left_cleared += self.particle_water().unwrap_or(0) + pending * q;
        }
        if let Some(w) = &mut self.water {
            self.dev
                .queue
                .write_buffer(&w.state, 0, bytemuck::cast_slice(&[0u32, 0]));
            w.bound = 0;
            w.pending = 0;
        }
        if self.water_share.is_some() {
            // The host draws the particles: its next frame shows them gone.
            self.vertices_current = false;
        }
    }

    pub(super) fn create_water(&self) -> Result<WaterGpu> {
        let d = &self.dev.device;
        let cap = self.params.water.capacity as u64;
        let particles = [
            b::buffer(d, "particles_a", cap * 32, STORAGE),
            b::buffer(d, "particles_b", cap * 32, STORAGE),
        ];
        // The hashed grid's table for the capacity (a step's table, sized by the particles it
        // holds, is at most this).
        let max_buckets = buckets_for(cap as usize) as u64;
        let force_words = if self.consts.gathered {
            b::wet_words::words(cap as u32, max_buckets as u32, self.points)
        } else {
            cap * WATER_FORCE_WORDS as u64
        };
        let force = b::buffer(d, "water_force", force_words * 4, STORAGE);
        let grid_count = b::buffer(d, "grid_count", (GRID_COUNT_HEADER as u64 + max_buckets) * 4, STORAGE);
        // Header, start[0..=buckets], the prefix sum's per-block totals, the mark table.
        let (mark_at, grid_words) = b::grid_words(max_buckets as u32);
        let grid = b::buffer(d, "grid", grid_words as u64 * 4, STORAGE);
        self.dev
            .queue
            .write_buffer(&grid, gh::MARK_AT as u64 * 4, bytemuck::bytes_of(&mark_at));
        let state = b::buffer(d, "water_state", b::water_state::WORDS as u64 * 4, STORAGE);
        let dispatch = b::buffer(d, "grid_dispatch", 16, STORAGE | wgpu::BufferUsages::INDIRECT);
        // Particles added in one frame; the whole capacity at most.
        let incoming = b::buffer(d, "water_incoming", cap * 32, STORAGE);
        // Absorption's per-particle scratch, then in a guide groom each point's bundle (what
        // absorption asks by, and eq. 2's reaction pulls with); a placeholder of 16 bytes
        // without either.
        let absorbs = self.params.held_water.absorbs();
        let bundle_words = if self.consts.bundle_points > 0 { self.points } else { 0 };
        let absorb_words = b::absorb_words::bundles_at(absorbs, cap as u32, self.points) + bundle_words;
        let absorb = b::buffer(d, "water_absorb", (absorb_words as u64 * 4).max(16), STORAGE);
        self.write_bundles(&absorb);
        let build_layout = pl::layout(
            d,
            "water build",
            &[
                Slot::Uniform,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::Read,
            ],
        );
        let dispatch_layout = pl::layout(d, "grid dispatch", &[Slot::ReadWrite]);
        let dispatch_bg = pl::bind(d, "grid dispatch", &dispatch_layout, &[&dispatch], None);
        let hair_layout = pl::layout(
            d,
            "water hair",
            &[Slot::ReadWrite, Slot::ReadWrite, Slot::Read, Slot::ReadWrite],
        );
        // The build binds the grid twice, apart: the mark table as atomics, the rest as words.
        let range = |from: u32, to: u32| {
            wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &grid,
                offset: from as u64 * 4,
                size: std::num::NonZeroU64::new((to - from) as u64 * 4),
            })
        };
        let mk_build = |i: usize| {
            let resources = vec![
                self.params_buf.as_entire_binding(),
                particles[i].as_entire_binding(),
                particles[1 - i].as_entire_binding(),
                range(mark_at, grid_words),
                grid_count.as_entire_binding(),
                range(0, mark_at),
                state.as_entire_binding(),
                incoming.as_entire_binding(),
            ];
            pl::bind_resources(d, "water build", &build_layout, resources)
        };
        let mk_hair = |i: usize| {
            pl::bind(
                d,
                "water hair",
                &hair_layout,
                &[&particles[1 - i], &force, &grid, &absorb],
                None,
            )
        };
        let water_mod = pl::module(d, "water", &pl::water_source(self.consts));
        let pipes = WATER_ENTRIES
            .iter()
            .map(|&e| {
                let layouts: &[&wgpu::BindGroupLayout] = if e == "grid_setup" {
                    &[&build_layout, &dispatch_layout]
                } else {
                    &[&build_layout]
                };
                pl::pipelines(d, &water_mod, layouts, &[e]).remove(0)
            })
            .collect();
        let wet_passes = pass_list(&self.params, self.integrator, self.bend, true);
        let wet_hair = HairKernels::new(
            d,
            self.consts,
            &wet_passes,
            &self.hair_layout,
            Some(&hair_layout),
            self.strands_layout.as_ref(),
            self.bridges.as_ref().map(|b| &b.cohesion_layout),
        );
        let piles = self.params.coalesces().then(|| {
            PilesGpu::new(
                &self.dev,
                self.consts,
                &self.params_buf,
                &particles,
                &state,
                &grid,
                self.params.water.capacity,
            )
        });
        let reactions = self.consts.gathered.then(|| {
            ReactionsGpu::new(
                d,
                self.consts,
                &self.params_buf,
                &particles,
                &grid,
                &force,
                &absorb,
                self.points,
                max_buckets as u32,
            )
        });
        self.dev.check()?;
        Ok(WaterGpu {
            build_bg: [mk_build(0), mk_build(1)],
            dispatch_bg,
            hair_bg: [mk_hair(0), mk_hair(1)],
            particles,
            force,
            grid_count,
            grid,
            state,
            dispatch,
            incoming,
            absorb,
            pipes,
            wet_hair,
            hair_layout,
            cur: 0,
            bound: 0,
            pending: 0,
            removed: 0,
            piles,
            reactions,
        })
    }

    /// Every particle (blocking), sorted by its record's bits.
    ///
    /// The device stores particles in the order its atomics handed out slots (append, cull,
    /// grid scatter), which changes run to run and with how steps are batched; every law
    /// reads them order-free (integer reaction sums, deterministic absorption winners), so
    /// the set is the same bits every run (checked on an H100 at 30, 60 and 144 Hz hosts) and
    /// only its order is not. Sorting on read hands the host the same bits every run.
    pub fn read_water(&self) -> Result<Vec<ParticleGpu>> {
        let (st, _) = self.peek_status()?;
        let Some(w) = &self.water else { return Ok(Vec::new()) };
        let n = st.particles as u64;
        let bytes = self.read_buffers(&[(&w.particles[w.cur], n * 32)], None)?;
        let mut recs: Vec<ParticleGpu> = bytemuck::pod_collect_to_vec(&bytes[..n as usize * 32]);
        recs.sort_unstable_by_key(|p| (p.x.map(f32::to_bits), p.v.map(f32::to_bits), p.mass, p.left));
        Ok(recs)
    }

    /// The hashed grid built now over the held particles: its cell side, per-bucket particle
    /// counts and mark table (tests compare them with the CPU's `HashGrid` and `hash_marks`).
    pub fn read_grid(&mut self) -> Result<crate::engine::GpuGrid> {
        let Some(w) = &self.water else {
            return Err(Error::InvalidArgument("no water".into()));
        };
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            w.encode_grid(&mut pass, false);
        }
        self.dev.submit(enc.finish(), false);
        let bytes = self.read_buffers(&[(&w.grid, w.grid.size())], None)?;
        let g: &[u32] = bytemuck::cast_slice(&bytes);
        let word = |at: u32| g[at as usize];
        let cell = f32::from_bits(word(gh::CELL));
        let start = |b: usize| g[gh::START as usize + b];
        let counts = (0..word(gh::BUCKETS) as usize)
            .map(|b| start(b + 1) - start(b))
            .collect();
        let at = word(gh::MARK_AT) as usize;
        let marks = g[at..at + word(gh::MARKS) as usize].to_vec();
        // Without the scatter the counts stay: clear them for the next build (whose
        // `grid_bounds` clears the marks).
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&w.grid_count, 0, None);
        self.dev.submit(enc.finish(), false);
        self.dev.wait()?;
        Ok(crate::engine::GpuGrid { cell, counts, marks })
    }
}
