//! [`Simulation`]: the Rust API every front end (C ABI, examples, tests) goes through.

mod auto;
mod budget;
mod estimate;
mod fixed;
mod frames;
mod guides;
mod roots;

pub use estimate::ErrorEstimate;
pub use fixed::Advance;

pub use crate::engine::BackendInfo;
use crate::engine::Engine;
use crate::error::{invalid, Error, Result};
use crate::groom::Groom;
use crate::params::{Backend, SimParams, VertexAttributes};
use crate::physics::clumping::{level_points, mean_nearest_tip_distance, mean_of_levels, ALONG_STRAND_LEVELS};
use crate::physics::spring::spring_energy;
use crate::plan::Pass;
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
    /// Mean distance from each strand tip to the nearest other tip, m (drops as hair clumps);
    /// -1 from [`Simulation::counters`], which does not measure it.
    pub clumping: f32,
    /// Worker threads.
    pub threads: u32,
    /// The integrator the last step ran (`Auto` resolved; under an error budget AUTO may
    /// change it from one frame to the next: `sim/auto.rs`).
    pub integrator: crate::Integrator,
    /// The backend in use (`Auto` resolved).
    pub backend: Backend,
    /// Mean distance from a strand's point to the nearest other strand's point at the same
    /// place along its strand, averaged over the quarter points (tips included), m: the
    /// clumping of long hair, which bundles along its length before its tips gather; -1 from
    /// [`Simulation::counters`].
    pub clumping_along: f32,
    /// How far the positions are from the exact solution of the model, m, estimated on every
    /// N-th strand ([`SimParams::error_estimate_stride`]); `None` when off, and while water
    /// couples strands (particles, liquid bridges: see `sim/estimate.rs`), and from
    /// [`Simulation::counters`].
    pub error_estimate: Option<ErrorEstimate>,
    /// The substeps the last step ran: the error budget's choice ([`SimParams::tolerance`]),
    /// else [`SimParams::substeps`].
    pub substeps: u32,
    /// Hair-particle pairs the last step's adhesion pulled, over its substeps: the work the
    /// water's cost follows (see [`crate::engine::Counters::adhesion_pairs`]; 0 on the GPU).
    pub adhesion_pairs: u64,
}

/// Per-point data in the host's order, for diagnostics that both backends share.
#[derive(Debug)]
struct HostPoints {
    strand_first: Vec<u32>,
    mass: Vec<f32>,
    pinned: Vec<bool>,
    /// Springs to the next and the next-but-one point (zero where there is none).
    springs: Vec<crate::plan::PointSprings>,
}

impl HostPoints {
    fn new(g: &Groom, p: &SimParams) -> Self {
        HostPoints {
            strand_first: g.strand_first.clone(),
            mass: g.masses().to_vec(),
            pinned: g.pinned().to_vec(),
            springs: crate::plan::point_springs(g, p),
        }
    }
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
    engine: Box<dyn Engine>,
    info: BackendInfo,
    host: HostPoints,
    head: Affine3A,
    head_prev: Affine3A,
    /// The SDF colliders' frames (empty without SDFs).
    sdf_frames: frames::MovingFrames,
    /// The analytic colliders' own frames (empty where they follow the head).
    collider_frames: frames::MovingFrames,
    /// Skinned roots' frames (scenes with them only).
    roots: Option<roots::RootTargets>,
    last_step_ms: f32,
    max_speed: f32,
    steps: u64,
    /// Simulated time since creation or reset, s (the wind's gusts and the emitters follow it).
    time: f64,
    /// Rain and spray (none by default), and the drops of this step (reused: no allocation
    /// once they have grown).
    emitters: [Option<crate::emit::Emitter>; 2],
    emit_pos: Vec<Vec3>,
    emit_vel: Vec<Vec3>,
    failed: Option<Error>,
    /// The live error estimate's shadow (none unless asked for).
    shadow: Option<estimate::Shadow>,
    /// The error budget (none without a tolerance) and the substeps it reads the sampled
    /// positions into (no allocation per step once grown).
    budget: Option<budget::Budget>,
    budget_x: Vec<Vec3>,
    /// Whether the budget reads the sampled points one step behind (the GPU: no wait for the
    /// step just submitted; `Engine::sample_every_step`).
    budget_behind: bool,
    /// Substeps of the next step, and of the last.
    substeps: u32,
    last_substeps: u32,
    /// The integrator of the last step (AUTO under a budget may change it for the next).
    last_integrator: crate::Integrator,
    /// Fixed-step updates' owed time ([`Simulation::advance`]).
    fixed: fixed::Accumulator,
    /// Where the engine's output lies between the last two steps (fixed steps with
    /// interpolation, after an `advance` that stepped); `None`: the last step itself.
    blend: Option<f32>,
    /// Guides and followers (scenes with guides only): the backend simulates the guides.
    guides: Option<guides::GuideState>,
    /// Vertices written per output: every host point (followers included), and their strands.
    vertex_points: usize,
    vertex_strands: usize,
}

impl Simulation {
    /// Validates `params` and lays out `groom` (copied; the groom may be dropped after).
    pub fn new(groom: &Groom, params: SimParams) -> Result<Self> {
        params.validate()?;
        let (guides, simulated) = Self::guides_of(groom, &params)?;
        let g = simulated.as_ref().unwrap_or(groom);
        let followers = guides.as_ref().map(|s| s.followers());
        let (engine, info) = crate::engine::create(g, &params, &Affine3A::IDENTITY, followers)?;
        Self::with_engine(g, groom, params, engine, info, guides)
    }

    /// The guides' state and the guide groom, where `params` asks for guides.
    fn guides_of(groom: &Groom, params: &SimParams) -> Result<(Option<guides::GuideState>, Option<Groom>)> {
        if !params.guides.enabled() {
            return Ok((None, None));
        }
        let (st, g) = guides::GuideState::new(groom, &params.guides, params.skinned_roots)?;
        Ok((Some(st), Some(g)))
    }

    /// A simulation at rest under the identity head transform, on `engine`, which simulates
    /// `groom` (the guide groom when `guides` is on) and writes the vertices of
    /// `host_groom`'s strands (the groom the host gave).
    fn with_engine(
        groom: &Groom,
        host_groom: &Groom,
        params: SimParams,
        mut engine: Box<dyn Engine>,
        info: BackendInfo,
        mut guides: Option<guides::GuideState>,
    ) -> Result<Self> {
        let head = Affine3A::IDENTITY;
        let vertex_points = host_groom.point_count();
        let keep_prev = guides.is_some() && params.fixed_step.on() && params.fixed_step.interpolate;
        let mut roots = params
            .skinned_roots
            .then(|| roots::RootTargets::new(host_groom, guides.as_ref().map(|g| g.host_strands()), keep_prev));
        if let Some(g) = &mut guides {
            g.start(engine.as_mut())?;
            engine.set_active_strands(g.stepping());
            g.pose(&head, roots.as_mut().map_or(&[], |r| r.shown(None)), engine.as_mut());
        }
        let host = HostPoints::new(groom, &params);
        let mut shadow = estimate::Shadow::new(groom, &params, engine.integrator())?;
        let budget = budget::Budget::new(&params, engine.integrator(), || {
            crate::plan::integrator::explicit_max_substep(&params, groom)
        })
        .filter(|_| shadow.is_some());
        let budget_behind = match (&budget, &mut shadow) {
            (Some(_), Some(sh)) if engine.sample_every_step(sh.points()) => {
                sh.keep_behind();
                true
            }
            _ => false,
        };
        let substeps = params.substeps;
        let sdf_frames = frames::MovingFrames::new(params.sdfs.iter().map(|s| s.transform).collect());
        let collider_frames = frames::MovingFrames::new(params.collider_frames.clone());
        let engine_integrator = engine.integrator();
        Ok(Simulation {
            params,
            engine,
            info,
            host,
            head,
            head_prev: head,
            sdf_frames,
            collider_frames,
            roots,
            last_step_ms: 0.0,
            max_speed: 0.0,
            steps: 0,
            time: 0.0,
            emitters: [None, None],
            emit_pos: Vec::new(),
            emit_vel: Vec::new(),
            failed: None,
            shadow,
            budget,
            budget_x: Vec::new(),
            budget_behind,
            substeps,
            last_substeps: substeps,
            last_integrator: engine_integrator,
            fixed: fixed::Accumulator::default(),
            blend: None,
            vertex_strands: guides
                .as_ref()
                .map_or(groom.strand_count(), |g| g.followers().follow.len()),
            guides,
            vertex_points,
        })
    }

    /// Creates a simulation on the host's own VkDevice (feature `vulkan`): the GPU backend runs
    /// there, and [`Simulation::vulkan_frame`] hands out the vertex `VkBuffer`. The host must
    /// have enabled what [`crate::gpu::vulkan::requirements`] lists; `params.backend` must not
    /// be [`Backend::CPU`].
    #[cfg(feature = "vulkan")]
    pub fn new_on_vulkan(groom: &Groom, params: SimParams, host: &crate::gpu::vulkan::HostVulkan) -> Result<Self> {
        params.validate()?;
        if params.backend == Backend::CPU {
            return Err(invalid!(
                "a simulation on the host's VkDevice runs the GPU backend, not the CPU one"
            ));
        }
        let (guides, simulated) = Self::guides_of(groom, &params)?;
        let g = simulated.as_ref().unwrap_or(groom);
        let integrator = crate::plan::resolve_integrator(&params, g);
        let dev = crate::gpu::vulkan::open(host)?;
        let follower_points = guides.as_ref().map(|_| groom.point_count());
        let (mut engine, info) =
            crate::engine::create_gpu(dev, g, &params, integrator, &Affine3A::IDENTITY, follower_points)?;
        if let Some(st) = &guides {
            engine.set_followers(st.followers())?;
        }
        Self::with_engine(g, groom, params, engine, info, guides)
    }

    /// The vertex buffer as the host's Vulkan sees it, holding the last step's vertices, and
    /// the semaphore values that order the host's reads against the next step's write. Only
    /// for simulations made with [`Simulation::new_on_vulkan`].
    #[cfg(feature = "vulkan")]
    pub fn vulkan_frame(&mut self) -> Result<crate::gpu::vulkan::SharedFrame> {
        self.on_shared_device(|e| e.shared_frame())
    }

    /// The water particles as the host's Vulkan sees them (positions and the indirect draw's
    /// arguments), written with each frame's vertices. Only for simulations made with
    /// [`Simulation::new_on_vulkan`].
    #[cfg(feature = "vulkan")]
    pub fn vulkan_water(&mut self) -> Result<crate::gpu::vulkan::SharedWater> {
        self.on_shared_device(|e| e.shared_water())
    }

    /// Runs `f` on the engine of a simulation that may share the host's VkDevice (others
    /// refuse), recording a failure as every read does.
    #[cfg(feature = "vulkan")]
    fn on_shared_device<T>(&mut self, f: impl FnOnce(&mut dyn Engine) -> Result<T>) -> Result<T> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let r = f(self.engine.as_mut());
        self.settle(r)
    }

    /// Number of strands in the simulated groom (with guides, the guides).
    pub fn strand_count(&self) -> usize {
        self.host.strand_first.len() - 1
    }

    /// The parameters the simulation was created with.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// Sets where the head is at the end of the next step (column-major 4×4, affine, no
    /// reflection). Pinned points and colliders move from the previous transform to this one
    /// over the step's substeps.
    pub fn set_head_transform(&mut self, m: Mat4) -> Result<()> {
        self.check_device()?;
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

    /// Sets where SDF collider `index` is at the end of the next step (its grid frame to the
    /// world: rotation, translation and a uniform scale, column-major). It moves there from
    /// where the last step left it over the step's substeps, as the head does.
    pub fn set_sdf_transform(&mut self, index: usize, m: Mat4) -> Result<()> {
        self.check_device()?;
        let n = self.sdf_frames.len();
        if index >= n {
            return Err(invalid!("SDF index {index}: the simulation has {n} SDF colliders"));
        }
        let t = crate::physics::frames::transform_from_mat4(m, &format!("SDF {index}"))?;
        self.sdf_frames.set(index, t);
        Ok(())
    }

    /// Sets where collider `index`'s own frame (a bone's) is at the end of the next step: the
    /// frame to the world, a rotation, a translation and a uniform scale, column-major. It
    /// moves there from where the last step left it over the step's substeps, as the head
    /// does. Only for simulations made with [`SimParams::collider_frames`]; where colliders
    /// follow the head, [`Error::Unsupported`].
    pub fn set_collider_transform(&mut self, index: usize, m: Mat4) -> Result<()> {
        self.check_device()?;
        if self.collider_frames.is_empty() {
            return Err(Error::Unsupported(
                "the colliders follow the head: give SimParams::collider_frames (WetHairSimDesc::collider_frames) to move them on frames of their own".into(),
            ));
        }
        let n = self.collider_frames.len();
        if index >= n {
            return Err(invalid!("collider index {index}: the simulation has {n} colliders"));
        }
        let t = crate::physics::frames::transform_from_mat4(m, &format!("collider {index}'s frame"))?;
        self.collider_frames.set(index, t);
        Ok(())
    }

    /// Adds water particles at `pos` with velocities `vel` (empty: at rest).
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        self.check_device()?;
        self.engine.add_water(pos, vel)?;
        if let (Some(sh), false) = (&mut self.shadow, pos.is_empty()) {
            sh.couple();
        }
        Ok(())
    }

    /// Removes every water particle (hair stays as wet as it is).
    pub fn clear_water(&mut self) -> Result<()> {
        self.check_device()?;
        self.engine.clear_water();
        Ok(())
    }

    /// A failed device fails every later call, as the header promises: the failure recorded,
    /// or one the device reports now (recorded from here on).
    pub fn check_device(&mut self) -> Result<()> {
        let r = self.device_ok();
        self.settle(r)
    }

    /// [`Simulation::check_device`] without recording: for the reads that take `&self`.
    pub fn device_ok(&self) -> Result<()> {
        if let Some(e @ Error::Device(_)) = &self.failed {
            return Err(e.clone());
        }
        self.engine.device_failure().map_or(Ok(()), Err)
    }

    /// Advances the simulation by `dt` seconds (0 < dt <= 1).
    ///
    /// A step that produces a non-finite value returns [`Error::Unstable`] and marks the
    /// simulation failed: further steps and vertex reads return the same error until
    /// [`Simulation::reset`]. On the GPU backend the step returns once its work is submitted,
    /// so a failure inside it is reported by the next read (vertices, stats or step).
    pub fn step(&mut self, dt: f32) -> Result<()> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if !(dt.is_finite() && dt > 0.0 && dt <= MAX_DT) {
            return Err(invalid!("dt must be finite, > 0 and <= {MAX_DT} s, got {dt}"));
        }
        if self.blend.is_some() {
            // A step of the host's own shows the state it reached.
            self.show_blend(None);
        }
        self.teleport_roots()?;
        self.step_to(dt, self.head, None)
    }

    /// One step of `dt` (checked) that moves the head from where the last step left it to
    /// `to`, and the SDFs and skinned roots to their set transforms, or `a` of the way there
    /// from where the frame began (`frame`: fixed steps inside a frame, after
    /// [`Simulation::mark_frame_start`]).
    fn step_to(&mut self, dt: f32, to: Affine3A, frame: Option<f32>) -> Result<()> {
        let t0 = Instant::now();
        let (engine, shadow) = (&mut self.engine, &mut self.shadow);
        self.sdf_frames.step_with(frame, |from, to| {
            if let Some(sh) = shadow {
                sh.place_sdfs(to);
            }
            engine.place_sdfs(from, to)
        })?;
        self.collider_frames.step_with(frame, |from, to| {
            if let Some(sh) = shadow {
                sh.place_colliders(to);
            }
            engine.place_colliders(from, to)
        })?;
        self.place_roots(frame)?;
        if let Some(b) = &self.budget {
            let n = b.before(self.engine.integrator(), self.substeps, dt);
            self.use_substeps(n);
        }
        self.emit(dt)?;
        if self.params.wind.blows() {
            self.engine.set_wind(self.params.wind.at(self.time));
        }
        if let Some(g) = &mut self.guides {
            let roots = self.roots.as_mut().map_or(&[][..], |r| r.shown(self.blend));
            g.before_step(dt, &to, roots, self.engine.as_mut())?;
        }
        let r = self.engine.step(dt, &self.head_prev, &to);
        if let (Some(sh), true) = (&mut self.shadow, r.is_ok()) {
            sh.step(dt, to);
        }
        self.time += dt as f64;
        self.last_substeps = self.substeps;
        self.last_integrator = self.engine.integrator();
        if r.is_ok() {
            let b = self.spend_budget(dt);
            self.settle(b)?;
        }
        self.last_step_ms = t0.elapsed().as_secs_f32() * 1e3;
        self.head_prev = to;
        self.steps += 1;
        self.settle(r).map(|v| self.max_speed = v)
    }

    /// The error budget's choice of the next step's substeps (and AUTO's integrator), from
    /// the estimate after this one of `dt` (reads the sampled points: on the GPU, a wait for
    /// the step).
    fn spend_budget(&mut self, dt: f32) -> Result<()> {
        let (Some(b), Some(sh)) = (&mut self.budget, &mut self.shadow) else {
            return Ok(());
        };
        let err = if sh.withheld() {
            None
        } else if self.budget_behind {
            // The step before the last, which the device has finished: no wait for this one.
            if self.engine.sampled_behind(&mut self.budget_x)? {
                sh.estimate_behind(&self.budget_x).map(|e| e.max)
            } else {
                None
            }
        } else {
            self.engine.positions_of(sh.points(), &mut self.budget_x)?;
            sh.estimate_at(self.budget_x.iter().copied()).map(|e| e.max)
        };
        let cur = self.engine.integrator();
        let c = b.next(cur, self.substeps, err, dt);
        if c.integrator != cur {
            match self.engine.set_integrator(c.integrator) {
                Ok(()) => sh.set_integrator(c.integrator),
                Err(Error::Unsupported(_)) => {
                    b.refuse(c.integrator);
                    return Ok(());
                }
                Err(e) => return Err(e),
            }
        }
        self.use_substeps(c.substeps);
        Ok(())
    }

    /// Runs `n` substeps from the next step on (engine and shadow).
    fn use_substeps(&mut self, n: u32) {
        if n != self.substeps {
            self.substeps = n;
            self.engine.set_substeps(n);
            if let Some(sh) = &mut self.shadow {
                sh.set_substeps(n);
            }
        }
    }

    /// Records a failure so that later calls repeat it.
    fn settle<T>(&mut self, r: Result<T>) -> Result<T> {
        if let Err(e) = &r {
            if matches!(e, Error::Unstable { .. } | Error::Device(_)) {
                self.failed = Some(e.clone());
            }
        }
        r
    }

    /// Back to the rest pose at the current head transform: zero velocity, dry, no water,
    /// counters cleared, failure forgotten. A failed GPU device stays failed: the reset
    /// returns its error and changes nothing.
    pub fn reset(&mut self) -> Result<()> {
        self.check_device()?;
        self.engine.reset(&self.head);
        self.reset_roots(&self.head.clone())?;
        if let Some(g) = &mut self.guides {
            let roots = self.roots.as_mut().map_or(&[][..], |r| r.shown(None));
            g.reset(&self.head, roots, self.engine.as_mut())?;
        }
        if let Some(sh) = &mut self.shadow {
            if let Some(r) = &self.roots {
                sh.set_root_targets(r);
            }
            // The shadow's frames are where the host last set them too, unswept.
            sh.place_sdfs(self.sdf_frames.targets());
            sh.place_colliders(self.collider_frames.targets());
            sh.reset(self.head);
        }
        if let Some(b) = &mut self.budget {
            b.reset();
            if let Some(start) = b.start().filter(|&i| i != self.engine.integrator()) {
                self.engine.set_integrator(start)?;
                if let Some(sh) = &mut self.shadow {
                    sh.set_integrator(start);
                }
            }
            self.use_substeps(self.params.substeps);
        }
        self.last_substeps = self.substeps;
        self.last_integrator = self.engine.integrator();
        self.reset_fixed();
        self.head_prev = self.head;
        self.sdf_frames.reset();
        self.collider_frames.reset();
        self.failed = None;
        self.steps = 0;
        self.time = 0.0;
        self.max_speed = 0.0;
        Ok(())
    }

    /// Sets the rain from the next step on (`None` stops it). See [`crate::emit::Rain`].
    pub fn set_rain(&mut self, rain: Option<crate::emit::Rain>) -> Result<()> {
        self.set_emitter(0, rain.map(crate::emit::Emitter::Rain))
    }

    /// Sets the spray from the next step on (`None` stops it). See [`crate::emit::Spray`].
    pub fn set_spray(&mut self, spray: Option<crate::emit::Spray>) -> Result<()> {
        self.set_emitter(1, spray.map(crate::emit::Emitter::Spray))
    }

    fn set_emitter(&mut self, slot: usize, e: Option<crate::emit::Emitter>) -> Result<()> {
        if let Some(e) = &e {
            e.validate()?;
        }
        self.emitters[slot] = e;
        Ok(())
    }

    /// Adds the drops the emitters make over the coming step, rain first. What does not fit
    /// the particle capacity is left out (the emitters do not wait).
    fn emit(&mut self, dt: f32) -> Result<()> {
        if self.emitters.iter().all(Option::is_none) {
            return Ok(());
        }
        self.emit_pos.clear();
        self.emit_vel.clear();
        for e in self.emitters.iter().flatten() {
            for k in e.drops_between(self.time, dt as f64) {
                let (x, v) = e.drop(k);
                self.emit_pos.push(x);
                self.emit_vel.push(v);
            }
        }
        let n = self.emit_pos.len().min(self.engine.particle_room());
        if n == 0 {
            return Ok(());
        }
        if let Some(sh) = &mut self.shadow {
            sh.couple();
        }
        match self.engine.add_water(&self.emit_pos[..n], &self.emit_vel[..n]) {
            Err(Error::Capacity(_)) => Ok(()), // a count that lags on the GPU: next frame
            r => r,
        }
    }

    /// Sets the wind from the next step on (see [`crate::Wind`]): its mean velocity, gusts and
    /// seed. The gusts follow the simulation's own clock, so a replay blows the same.
    pub fn set_wind(&mut self, wind: crate::Wind) -> Result<()> {
        wind.validate()?;
        self.params.wind = wind;
        self.engine.set_wind(wind.at(self.time));
        if let Some(sh) = &mut self.shadow {
            sh.set_wind(wind);
        }
        Ok(())
    }

    /// Whether a step failed and the simulation waits for a reset.
    pub fn failed(&self) -> Option<&Error> {
        self.failed.as_ref()
    }

    /// Which backend runs the simulation, on what device, and why `Auto` chose it.
    pub fn backend_info(&self) -> &BackendInfo {
        &self.info
    }

    /// Simulates the first `fraction` of the guides (0 < fraction <= 1; `SimParams::guides`
    /// on, else `Unsupported`) from the next step on, as a host lowers detail with distance:
    /// the guides of a lower fraction are the first of the spread order, so any fraction
    /// keeps them even over the scalp. The output blends from the old guides to the new over
    /// `Guides::blend_time`; guides that start to be simulated start where the output showed
    /// them (on the GPU a blocking read of the guides), so nothing pops.
    pub fn set_guide_fraction(&mut self, fraction: f32) -> Result<()> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if !(fraction > 0.0 && fraction <= 1.0) {
            return Err(invalid!("the guide fraction must be in (0, 1], got {fraction}"));
        }
        let Some(g) = &mut self.guides else {
            return Err(Error::Unsupported(
                "this simulation has no guides (SimParams::guides)".into(),
            ));
        };
        let roots = self.roots.as_mut().map_or(&[][..], |r| r.shown(None));
        let r = g.set_fraction(fraction, roots, self.engine.as_mut());
        self.settle(r)
    }

    /// Guides simulated now and guides in all (`None` without guides).
    pub fn guide_counts(&self) -> Option<(usize, usize)> {
        self.guides.as_ref().map(|g| g.counts())
    }

    /// The host strand of each guide in the order the backend holds them (its point states,
    /// positions and tips are theirs); `None` without guides.
    pub fn guide_strands(&self) -> Option<&[u32]> {
        self.guides.as_ref().map(|g| g.host_strands())
    }

    /// Hair points written per [`Simulation::write_vertices`] (every strand of the groom,
    /// followers included).
    pub fn vertex_count(&self) -> usize {
        self.vertex_points
    }

    /// Strand and point counts.
    pub fn stats_counts(&self) -> (u32, u32) {
        (self.vertex_strands as u32, self.vertex_count() as u32)
    }

    /// The attributes written per vertex.
    pub fn attributes(&self) -> VertexAttributes {
        self.params.attributes
    }

    /// Writes the requested attributes of every point, interleaved, strand after strand.
    /// `dst` must hold at least `vertex_count() * stride` floats; returns the floats written.
    /// Writes nothing on error. On the GPU backend with [`crate::Readback::PREVIOUS_FRAME`] the
    /// vertices are those of the step before the last (see [`crate::Readback`]).
    pub fn write_vertices(&mut self, dst: &mut [f32]) -> Result<usize> {
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
        let r = self.engine.write_vertices(&mut dst[..n]).map(|_| n);
        self.settle(r)
    }

    /// Wets every hair point up to `s` times its hold limit (docs/WET_MODEL.md §1: its
    /// capacity and the water between its fibres), as when a character steps out of water;
    /// never removes water. 1 is as wet as hair stays; above 1 (up to
    /// [`wet::MAX_SOAK`](crate::physics::wet::MAX_SOAK)) the excess runs down the strands and
    /// drips, as from hair just out of a bath. Needs [`SimParams::held_water`] on (else
    /// `Unsupported`); `s` outside [0, MAX_SOAK] or NaN is refused, and so is `s` above 1 when
    /// nothing could drip (no flow and no absorption: no drip pass).
    pub fn soak(&mut self, s: f32) -> Result<()> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let most = crate::physics::wet::MAX_SOAK;
        if !(0.0..=most).contains(&s) {
            return Err(crate::error::Error::InvalidArgument(format!(
                "soak must be in [0, {most}] of the hold limit, got {s}"
            )));
        }
        let hw = self.params.held_water;
        if s > 1.0 && hw.enabled && !hw.drips() {
            return Err(crate::error::Error::InvalidArgument(format!(
                "soak {s} passes the hold limit, but nothing drips (flow_mobility and absorb_rate are 0)"
            )));
        }
        let r = self.engine.soak(s);
        if let (Some(sh), true) = (&mut self.shadow, r.is_ok()) {
            sh.soak(s);
        }
        self.settle(r)
    }

    /// Where the water went, in whole quanta (`None` without held water): added equals in
    /// particles plus held plus left plus evaporated, exactly. On the GPU a blocking read; if
    /// that fails (a lost device) this is `None` too: [`Simulation::try_water_ledger`] says why.
    pub fn water_ledger(&self) -> Option<crate::engine::WaterLedger> {
        self.try_water_ledger().ok().flatten()
    }

    /// [`Simulation::water_ledger`], with the device's failure as an error.
    pub fn try_water_ledger(&self) -> Result<Option<crate::engine::WaterLedger>> {
        self.engine.ledger().transpose()
    }

    /// The passes the next step will run (only those the scene needs), the same list on
    /// both backends.
    pub fn passes(&self) -> Vec<Pass> {
        self.engine.passes()
    }

    /// The GPU compute entry points one step dispatches (empty on the CPU backend).
    pub fn gpu_dispatches(&self) -> Vec<&'static str> {
        self.engine.gpu_dispatches()
    }

    /// Every buffer the simulation holds and its size in bytes.
    pub fn buffers(&self) -> Vec<(&'static str, usize)> {
        self.engine.buffers()
    }

    /// Every point's position, strand after strand (on the GPU a blocking readback; empty if
    /// the device failed).
    pub fn positions(&self) -> Vec<Vec3> {
        self.point_states()
            .map(|v| v.into_iter().map(|p| p.0).collect())
            .unwrap_or_default()
    }

    /// Every point's velocity, strand after strand (as [`Simulation::positions`]).
    pub fn velocities(&self) -> Vec<Vec3> {
        self.point_states()
            .map(|v| v.into_iter().map(|p| p.1).collect())
            .unwrap_or_default()
    }

    /// Position, velocity and wetness of every point, strand after strand.
    pub fn point_states(&self) -> Result<Vec<(Vec3, Vec3, f32)>> {
        self.engine.point_states()
    }

    /// Water particle positions and velocities (order changes when particles are removed; the
    /// GPU backend hands them sorted by their bits, the same order every run).
    /// On the GPU backend a read back that fails (a lost device) is an error, not no water.
    /// After a failed step it returns that failure: no non-finite particle is handed out.
    pub fn water(&self) -> Result<(Vec<Vec3>, Vec<Vec3>)> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        self.engine.water()
    }

    /// Water particle positions (order changes when particles are removed).
    pub fn water_positions(&self) -> Result<Vec<Vec3>> {
        Ok(self.water()?.0)
    }

    /// Water particle velocities, in the order of [`Simulation::water_positions`].
    pub fn water_velocities(&self) -> Result<Vec<Vec3>> {
        Ok(self.water()?.1)
    }

    /// Tip positions of every strand, in host order.
    pub fn tips(&self) -> Vec<Vec3> {
        self.tips_of(&self.positions())
    }

    /// The tips among `x` (every point, strand after strand; empty gives none).
    fn tips_of(&self, x: &[Vec3]) -> Vec<Vec3> {
        if x.is_empty() {
            return Vec::new();
        }
        self.host.strand_first[1..].iter().map(|&e| x[e as usize - 1]).collect()
    }

    /// Counters and measures. The measures are taken now: the clumping measures are five
    /// nearest-point searches over the strands (on the CPU backend's worker pool: 6.5 ms on
    /// the 10,000-strand paper scene and 75 ms on 100,000 strands, on 2 threads), and on the
    /// GPU this reads the state back and waits for the device. For every frame, read
    /// [`Simulation::counters`].
    pub fn stats(&self) -> Stats {
        let c = self.counters();
        let x = self.positions(); // one read back for both measures
        let (clumping, clumping_along) = self.clumping_of(&x);
        Stats {
            clumping,
            clumping_along,
            // Particles couple strands (drips from held water among them): no estimate now.
            error_estimate: self
                .shadow
                .as_ref()
                .filter(|_| c.particles == 0)
                .and_then(|sh| sh.estimate(&x)),
            ..c
        }
    }

    /// The counters of [`Simulation::stats`] without its measures (`clumping` and
    /// `clumping_along` are -1, `error_estimate` is `None`): no search and no read of the
    /// positions, so a host may read them every frame. On the GPU backend it still waits for
    /// the last step (the particle count is in a 32-byte status the device writes).
    pub fn counters(&self) -> Stats {
        let (strands, points) = self.stats_counts();
        let c = self.engine.counters();
        Stats {
            strands,
            points,
            particles: c.particles,
            particles_removed: c.particles_removed,
            steps: self.steps,
            last_step_ms: self.last_step_ms,
            max_speed: self.max_speed,
            clumping: -1.0,
            clumping_along: -1.0,
            threads: c.threads,
            integrator: self.last_integrator,
            backend: self.engine.kind(),
            error_estimate: None,
            substeps: self.last_substeps,
            adhesion_pairs: c.adhesion_pairs,
        }
    }

    /// The tip measure and the along-strand measure of the positions `x`: five independent
    /// nearest-point searches (the tips, and each of the quarter levels), run as jobs on the
    /// backend's pool, each into its own slot, and combined in a fixed order (the same bits
    /// on any thread count).
    fn clumping_of(&self, x: &[Vec3]) -> (f32, f32) {
        if x.is_empty() || self.host.strand_first.len() < 2 {
            return (mean_nearest_tip_distance(&self.tips_of(x)), 0.0);
        }
        let first = &self.host.strand_first;
        let sets: Vec<Vec<Vec3>> = std::iter::once(self.tips_of(x))
            .chain(ALONG_STRAND_LEVELS.map(|level| level_points(x, first, level)))
            .collect();
        let mut out = [0.0f32; 1 + ALONG_STRAND_LEVELS.len()];
        let mut jobs: Vec<Box<dyn FnMut() + Send + '_>> = out
            .iter_mut()
            .zip(&sets)
            .map(|(o, set)| Box::new(move || *o = mean_nearest_tip_distance(set)) as Box<dyn FnMut() + Send>)
            .collect();
        self.engine.run_jobs(&mut jobs);
        drop(jobs);
        let levels = std::array::from_fn(|k| out[1 + k]);
        (out[0], mean_of_levels(&levels))
    }

    /// The mass of host point `i` showing `wetness`, kg: its dry mass, plus its water under the
    /// wet model (`wetness` of its hold limit, `capacity_ratio + free_ratio` of the dry mass).
    fn point_mass(&self, i: usize, wetness: f32) -> f64 {
        let m = self.host.mass[i] as f64;
        let hw = &self.params.held_water;
        if hw.enabled {
            m * (1.0 + wetness as f64 * (hw.capacity_ratio as f64 + hw.free_ratio as f64))
        } else {
            m
        }
    }

    /// Total linear momentum of free hair points (with the water they hold) and water
    /// particles, kg·m/s.
    pub fn momentum(&self) -> DVec3 {
        let hair: DVec3 = self
            .point_states()
            .unwrap_or_default()
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.host.pinned[*i])
            .map(|(i, p)| p.1.as_dvec3() * self.point_mass(i, p.2))
            .sum();
        let m_w = self.params.water.particle_mass as f64;
        hair + self
            .water_velocities()
            .unwrap_or_default()
            .iter()
            .map(|v| v.as_dvec3() * m_w)
            .sum::<DVec3>()
    }

    /// Kinetic, spring and gravitational energy (f64 sums; hair points weigh the water they
    /// hold and bend as limply as their saturation makes them).
    pub fn energy(&self) -> Energy {
        let g = self.params.gravity.as_dvec3();
        let mut e = Energy::default();
        let st = self.point_states().unwrap_or_default();
        let h = &self.host;
        for s in 0..h.strand_first.len().saturating_sub(1) {
            let (a, b) = (h.strand_first[s] as usize, h.strand_first[s + 1] as usize);
            for i in a..b.min(st.len()) {
                let (x, v, _) = st[i];
                if !h.pinned[i] {
                    let m = self.point_mass(i, st[i].2);
                    e.kinetic += 0.5 * m * v.as_dvec3().length_squared();
                    e.gravity -= m * g.dot(x.as_dvec3());
                }
                let sp = &h.springs[i];
                if i + 1 < b {
                    e.spring += spring_energy(sp.stretch.stiffness, sp.rest[0], (st[i + 1].0 - x).length());
                }
                if i + 2 < b {
                    // Limp where wet, as the step's bend springs are (`wet::bend_scale`).
                    let hw = &self.params.held_water;
                    let k = if hw.limp() {
                        let s = 0.5 * (st[i].2 + st[i + 2].2);
                        sp.bend.stiffness * crate::physics::wet::bend_scale(s, hw.wet_bend_ratio)
                    } else {
                        sp.bend.stiffness
                    };
                    e.spring += spring_energy(k, sp.rest[1], (st[i + 2].0 - x).length());
                }
            }
        }
        let m_w = self.params.water.particle_mass as f64;
        let (wx, wv) = self.water().unwrap_or_default();
        for (x, v) in wx.iter().zip(&wv) {
            e.kinetic += 0.5 * m_w * v.as_dvec3().length_squared();
            e.gravity -= m_w * g.dot(x.as_dvec3());
        }
        e
    }

    /// Makes a GPU simulation's device fail as a lost device would, to test a host's error
    /// path; later calls return [`Error::Device`]. Does nothing on the CPU backend.
    pub fn debug_lose_device(&mut self) {
        self.engine.lose_device();
        if let Some(e) = self.engine.device_failure() {
            self.failed = Some(e);
        }
    }

    /// Switches per-pass timing on (totals start from zero) or off. Returns whether the backend
    /// can: the CPU always (wall time, two clock reads per pass); the GPU where the adapter
    /// writes timestamps inside a compute pass (GPU time per stage, and each timed step waits
    /// for the GPU to read its timestamps back). Off, it costs a branch per pass.
    pub fn time_passes(&mut self, on: bool) -> bool {
        self.engine.time_passes(on)
    }

    /// Per-pass time since [`Simulation::time_passes`] switched it on, in step order, under
    /// the same stage names on both backends: where a frame's time goes (the benches print it).
    pub fn pass_times(&self) -> Vec<crate::engine::PassTime> {
        self.engine.pass_times()
    }

    /// Starts measuring each step's GPU time with timestamp queries (GPU backend, adapters with
    /// timestamps). Returns whether it could; costs one query resolve per step after.
    pub fn enable_gpu_timing(&mut self) -> bool {
        self.engine.enable_gpu_timing()
    }

    /// GPU time of the last step, ms, once [`Simulation::enable_gpu_timing`] succeeded (a
    /// blocking read; for benchmarks).
    pub fn last_step_gpu_ms(&self) -> Option<Result<f64>> {
        self.engine.last_step_gpu_ms()
    }

    /// Builds the GPU's hashed water grid over the particles held now and returns its cell
    /// side, per-bucket counts and mark table (tests compare them with the CPU's `HashGrid`
    /// and `hash_marks`). `None` on the CPU backend or without water.
    pub fn gpu_grid(&mut self) -> Option<Result<crate::engine::GpuGrid>> {
        self.engine.gpu_grid()
    }

    /// How many points searched for liquid bridges in the last step, on either backend
    /// (tests hold the backends to one search rule, `wet::bridge_searches`); `None` where the
    /// scene has no bridges.
    pub fn bridge_searches(&mut self) -> Option<Result<u32>> {
        self.engine.bridge_searches()
    }
}
