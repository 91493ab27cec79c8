//! The seam between [`crate::Simulation`] and its backends: the [`Engine`] trait both the CPU
//! and the GPU backend implement, and [`create`], which picks one as the parameters ask.
//! `Simulation` holds a `Box<dyn Engine>` and never asks which backend it has.

use crate::error::Result;
use crate::groom::Groom;
use crate::params::{Backend, Integrator, SimParams};
use crate::physics::followers::Followers;
use crate::physics::roots::RootFrame;
use crate::plan::Pass;
use glam::{Affine3A, Quat, Vec3};

/// Which backend runs the simulation, on what, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BackendInfo {
    /// [`Backend::CPU`] or [`Backend::GPU`].
    pub backend: Backend,
    /// The GPU adapter's name and API ("llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)"), or the
    /// CPU's thread count.
    pub device: String,
    /// Why [`Backend::AUTO`] chose the CPU (empty when it did not fall back).
    pub fallback_reason: String,
}

/// The GPU's hashed water grid as one build leaves it (tests compare it with the CPU's
/// `HashGrid` and `hash_marks`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuGrid {
    /// Cell side, m.
    pub cell: f32,
    /// Particles per bucket.
    pub counts: Vec<u32>,
    /// The mark table (`physics::hash_marks`); empty where the build has none.
    pub marks: Vec<u32>,
}

/// Counters a backend keeps (the rest of [`crate::Stats`] is the simulation's).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counters {
    /// Water particles now.
    pub particles: u32,
    /// Particles removed for leaving the domain since create or reset.
    pub particles_removed: u64,
    /// Worker threads (0 on the GPU).
    pub threads: u32,
    /// Hair-particle pairs the last step's adhesion pulled, summed over its substeps: the
    /// water's work, which its cost follows (the benches divide one by the other). The CPU
    /// counts a row of up to eight points, one per strand, and a particle (or a source of
    /// coalesced drops, `WaterParams::pile_cell`) within `r_max` of any of them as one pair (a row too wide for one query, point by point); 0 after a
    /// reset, and on the GPU, which does not count them.
    pub adhesion_pairs: u64,
}

/// Time one stage of the step took since timing was switched on
/// ([`crate::Simulation::time_passes`]): wall time on the CPU, GPU time on the GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's name (as in [`Pass::name`]), or the stage's where a backend runs several
    /// passes as one (the CPU's `blocks`).
    pub name: &'static str,
    /// Total milliseconds.
    pub ms: f64,
    /// How many times it ran.
    pub runs: u64,
}

/// Position, velocity and wetness of one hair point.
pub type PointState = (Vec3, Vec3, f32);

/// Where the water went, in whole quanta ([`crate::physics::wet::WATER_QUANTUM`] kg each):
/// `added == in_particles + held + left + evaporated`, exactly ([`WaterLedger::balanced`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WaterLedger {
    /// Water given since the last reset: particles the host added, and soaking.
    pub added: u64,
    /// In free particles now (drops the hair shed included).
    pub in_particles: u64,
    /// Held by the hair now.
    pub held: u64,
    /// Left the simulation since the last reset: particles that fell out of the domain, and
    /// particles the host cleared.
    pub left: u64,
    /// Evaporated from the hair since the last reset.
    pub evaporated: u64,
}

impl WaterLedger {
    /// Whether every quantum added is accounted for.
    pub fn balanced(&self) -> bool {
        self.added == self.in_particles + self.held + self.left + self.evaporated
    }
}

/// What a backend does for a simulation. Every method answers in the host's order (strand
/// after strand); the backend keeps its own layout behind it.
pub trait Engine: std::fmt::Debug + Send {
    /// [`Backend::CPU`] or [`Backend::GPU`].
    fn kind(&self) -> Backend;
    /// The integrator in use (`Auto` resolved).
    fn integrator(&self) -> Integrator;
    /// The passes the next step runs, in order ([`crate::plan::pass_list`] for this scene).
    fn passes(&self) -> Vec<Pass>;
    /// Adds water particles (checked by [`crate::plan::check_new_particles`]); storage is made
    /// at the first call.
    fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()>;
    /// Removes every particle (wetness stays).
    fn clear_water(&mut self);
    /// How many particles can still be added without exceeding the capacity, as far as the
    /// backend knows without waiting for the device (it may say fewer than there is room for).
    fn particle_room(&self) -> usize;
    /// Sets the wind the next step blows with, m/s (the simulation samples its gusts).
    fn set_wind(&mut self, wind: Vec3);
    /// Advances by `dt` in the configured substeps while the head moves `from` → `to`; returns
    /// the largest point speed known after it (the GPU's is the previous step's, as its last
    /// status read found it).
    fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<f32>;
    /// Back to the rest pose at `head`: zero velocity, dry, no water.
    fn reset(&mut self, head: &Affine3A);
    /// Runs `n` substeps per step from the next step on (the error budget's choice; `n` is at
    /// most the larger of the created substeps and `SimParams::max_substeps`).
    fn set_substeps(&mut self, n: u32);
    /// Runs `integrator` from the next step on, from the current state (the error budget's
    /// AUTO choice between symplectic Euler and BDF2; BDF2 starts from a backward Euler step).
    /// Refused where the backend cannot run it for this groom.
    fn set_integrator(&mut self, integrator: Integrator) -> Result<()>;
    /// The positions of the points `idx` (host order) into `out` (cleared first). The default
    /// reads every point; the CPU reads only those asked for.
    fn positions_of(&self, idx: &[u32], out: &mut Vec<Vec3>) -> Result<()> {
        let all = self.point_states()?;
        out.clear();
        out.extend(idx.iter().map(|&i| all[i as usize].0));
        Ok(())
    }
    /// From now on, keeps the positions of the points `idx` (host order) at the end of each
    /// step for [`Engine::sampled_behind`], so that reading them need not wait for the step
    /// just submitted. Returns false where [`Engine::positions_of`] costs no wait anyway (the
    /// CPU, the default).
    fn sample_every_step(&mut self, _idx: &[u32]) -> bool {
        false
    }
    /// The positions kept by [`Engine::sample_every_step`] at the end of the step before the
    /// last, into `out`; `Ok(false)` when there is none (the first step since create or reset).
    fn sampled_behind(&mut self, _out: &mut Vec<Vec3>) -> Result<bool> {
        Ok(false)
    }
    /// Moves the SDF colliders from `from` to `to` (grid frame to world, one per
    /// `SimParams::sdfs`) over the next step's substeps, as the head moves. Only called when
    /// the scene has SDFs.
    fn place_sdfs(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()>;
    /// Moves the analytic colliders' own frames from `from` to `to` (one per collider,
    /// `SimParams::collider_frames`) over the next step's substeps, as the head moves. Only
    /// called when the scene has collider frames.
    fn place_colliders(&mut self, from: &[Affine3A], to: &[Affine3A]) -> Result<()>;
    /// Moves the skinned roots from `from` to `to` (one frame per host strand) over the next
    /// step's substeps, as the head moves. Only called when the scene has skinned roots.
    fn place_roots(&mut self, from: &[RootFrame], to: &[RootFrame]) -> Result<()>;
    /// Carries host strands `strands` rigidly from root frames `from` to `to` (one each) now,
    /// velocities zeroed (a teleport, or a reset onto the frames), and starts BDF2 again.
    fn carry_strands(&mut self, strands: &[u32], from: &[RootFrame], to: &[RootFrame]) -> Result<()>;
    /// Keeps the positions now as where the output blend starts (fixed steps with
    /// interpolation, before an `advance`'s last step). The first call allocates the copy;
    /// an engine never asked keeps nothing.
    fn keep_previous(&mut self) -> Result<()>;
    /// The vertex output from now on: `None` the current state; `Some(a)` the positions kept
    /// by [`Engine::keep_previous`] moved toward the current ones by `a` in [0, 1]
    /// ([`crate::physics::lanes::L3::toward`]), tangents from the blended positions, wetness
    /// the current. Ignored until something is kept. The next vertex read (or shared frame)
    /// writes the blend, with or without a step between.
    fn blend_output(&mut self, a: Option<f32>);
    /// Guides and followers (`SimParams::guides`; this backend's strands are the guides): from
    /// now on [`Engine::write_vertices`] writes every host strand of `f` from the guides
    /// ([`crate::physics::followers::output_point`]). The first call makes the output's
    /// storage; later calls (a change of the simulated fraction) replace the bindings.
    fn set_followers(&mut self, f: &Followers) -> Result<()>;
    /// The followers' pose for the next output: the head's rotation their offsets turn with,
    /// how far the output has moved from `Followers::from` to `Followers::follow` (0..=1),
    /// and with skinned roots every host strand's root frame (else empty): each guide's frames
    /// start from its own, and each strand's root points land on its own
    /// (`physics/follow_roots.rs`).
    fn pose_followers(&mut self, head: Quat, blend: f32, roots: &[RootFrame]);
    /// Steps only the first `n` strands from the next step on (the guides a lower simulated
    /// fraction keeps; the others keep their state). The CPU steps whole blocks of 8.
    fn set_active_strands(&mut self, n: usize);
    /// Sets the state of the strands from `first` on to positions `x`, velocities `v` and
    /// wetness `wet` (their points, strand after strand), and starts BDF2 again: a guide that
    /// starts to be simulated starts where its followers' output showed it.
    fn seed_strands(&mut self, first: u32, x: &[Vec3], v: &[Vec3], wet: &[f32]) -> Result<()>;
    /// Writes the attributes the parameters ask for, of every point, into `dst`: exactly
    /// `points * params.attributes.stride()` floats (every host point with followers).
    fn write_vertices(&mut self, dst: &mut [f32]) -> Result<()>;
    /// Every point's state (on the GPU a blocking readback).
    fn point_states(&self) -> Result<Vec<PointState>>;
    /// Water positions and velocities (order changes when particles are removed).
    fn water(&self) -> Result<(Vec<Vec3>, Vec<Vec3>)>;
    /// Particle and thread counters.
    fn counters(&self) -> Counters;
    /// Runs independent jobs (the stats' measures) on the backend's worker pool where it has
    /// one, else one after another. Each job writes its own result, so what they compute does
    /// not depend on the thread count.
    fn run_jobs(&self, jobs: &mut [Box<dyn FnMut() + Send + '_>]) {
        jobs.iter_mut().for_each(|j| j());
    }
    /// Every buffer the backend holds and its size in bytes.
    fn buffers(&self) -> Vec<(&'static str, usize)>;
    /// Wets every free hair point up to `s` times its hold limit (held water; never removes water).
    fn soak(&mut self, _s: f32) -> Result<()> {
        Err(crate::error::Error::Unsupported(
            "held water is not simulated on this backend".into(),
        ))
    }
    /// Guides (docs/GUIDES.md "Water"): how many host strands' hair each strand stands for
    /// (`bundle`, in this backend's strand order): with held water its capacity and hold
    /// limit are the bundle's and a quantum weighs `1 / bundle` as much on it; with water
    /// particles it asks a drop for the bundle's water and pulls the drop back with the
    /// bundle's hair (eq. 2's reaction). `water`, where given, is each point's water after the
    /// simulation moved it between guides (quanta, in this backend's point order; the sum
    /// held may not change).
    fn set_bundles(&mut self, bundle: &[f32], water: Option<&[u32]>) -> Result<()>;
    /// Each point's held water, quanta, in this backend's point order (on the GPU a blocking
    /// readback); empty without held water.
    fn held_water(&self) -> Result<Vec<u32>>;
    /// Where the held water is, in quanta (`None` without held water; an error when the
    /// device could not be read).
    fn ledger(&self) -> Option<Result<WaterLedger>> {
        None
    }
    /// The GPU compute entry points one step dispatches (none on the CPU).
    fn gpu_dispatches(&self) -> Vec<&'static str> {
        Vec::new()
    }
    /// Makes a GPU device fail as a lost one would (tests of a host's error path).
    fn lose_device(&self) {}
    /// The device's failure, once it has failed (lost, out of memory, validation); never on
    /// the CPU.
    fn device_failure(&self) -> Option<crate::error::Error> {
        None
    }
    /// Switches per-pass wall timing on (totals from zero) or off; false where the backend
    /// cannot time its passes.
    fn time_passes(&mut self, _on: bool) -> bool {
        false
    }
    /// Per-pass totals since timing was switched on, in step order (empty when off).
    fn pass_times(&self) -> Vec<PassTime> {
        Vec::new()
    }
    /// Starts GPU timestamp queries around each step; false where there are none.
    fn enable_gpu_timing(&mut self) -> bool {
        false
    }
    /// GPU time of the last step, ms, once timing is enabled.
    fn last_step_gpu_ms(&self) -> Option<Result<f64>> {
        None
    }
    /// The GPU's hashed water grid built now over the particles: its cell side, per-bucket
    /// counts and mark table.
    fn gpu_grid(&mut self) -> Option<Result<GpuGrid>> {
        None
    }
    /// How many points searched for liquid bridges in the last step (`wet::bridge_searches`);
    /// `None` where the scene has no bridges.
    fn bridge_searches(&mut self) -> Option<Result<u32>> {
        None
    }
    /// The vertex buffer as the host's Vulkan sees it (host-shared GPU simulations only).
    #[cfg(feature = "vulkan")]
    fn shared_frame(&mut self) -> Result<crate::gpu::vulkan::SharedFrame> {
        Err(not_shared("the vertex VkBuffer is"))
    }
    /// The water as the host's Vulkan sees it (host-shared GPU simulations only).
    #[cfg(feature = "vulkan")]
    fn shared_water(&mut self) -> Result<crate::gpu::vulkan::SharedWater> {
        Err(not_shared("the water VkBuffers are"))
    }
}

/// The refusal of a Vulkan share by a simulation that does not run on the host's device.
#[cfg(feature = "vulkan")]
pub fn not_shared(what: &str) -> crate::error::Error {
    crate::error::Error::Unsupported(format!(
        "{what} shared only by simulations created on the host's VkDevice"
    ))
}

/// A backend for `groom` under `p`, as `p.backend` asks (see [`Backend`]), at rest under
/// `head`; with `followers` (guides: `groom` is the guide groom) its output writes every host
/// strand of theirs.
pub fn create(
    groom: &Groom,
    p: &SimParams,
    head: &Affine3A,
    followers: Option<&Followers>,
) -> Result<(Box<dyn Engine>, BackendInfo)> {
    let (mut e, info) = create_bare(groom, p, head, followers.map(|f| f.rest.len()))?;
    if let Some(f) = followers {
        e.set_followers(f)?;
    }
    Ok((e, info))
}

/// [`create`] without the followers' bindings; `vertex_points` sizes the GPU's vertex buffer
/// (the groom's points when `None`).
fn create_bare(
    groom: &Groom,
    p: &SimParams,
    head: &Affine3A,
    vertex_points: Option<usize>,
) -> Result<(Box<dyn Engine>, BackendInfo)> {
    let cpu = |reason: String| -> Result<(Box<dyn Engine>, BackendInfo)> {
        let c = crate::cpu::step::CpuBackend::new(groom, p, head)?;
        let info = BackendInfo {
            backend: Backend::CPU,
            device: format!("CPU, {} threads", c.threads()),
            fallback_reason: reason,
        };
        Ok((Box::new(c), info))
    };
    #[cfg(not(feature = "gpu"))]
    {
        let _ = vertex_points;
        let why = "this build has no GPU backend (feature `gpu`)";
        match p.backend {
            Backend::CPU => cpu(String::new()),
            Backend::GPU => Err(crate::error::Error::Unsupported(why.into())),
            Backend::AUTO => cpu(why.into()),
        }
    }
    #[cfg(feature = "gpu")]
    {
        let integrator = crate::plan::resolve_integrator(p, groom);
        match p.backend {
            Backend::CPU => cpu(String::new()),
            Backend::GPU => {
                let dev = crate::gpu::GpuDevice::open(true)?;
                create_gpu(dev, groom, p, integrator, head, vertex_points)
            }
            Backend::AUTO => {
                if integrator == Integrator::XPBD {
                    return cpu(format!("{integrator:?} runs on the CPU backend only"));
                }
                match crate::gpu::GpuDevice::open(false) {
                    Err(e) => cpu(e.to_string()),
                    Ok(dev) => match create_gpu(dev, groom, p, integrator, head, vertex_points) {
                        Ok(r) => Ok(r),
                        Err(e) => cpu(format!("the GPU backend failed to start: {e}")),
                    },
                }
            }
        }
    }
}

/// The GPU backend on `dev` (an adapter of ours, or the host's VkDevice), its vertex buffer
/// sized for `vertex_points` (the groom's points when `None`; the host's with followers, whose
/// bindings come next through [`Engine::set_followers`]).
#[cfg(feature = "gpu")]
pub fn create_gpu(
    dev: crate::gpu::GpuDevice,
    groom: &Groom,
    p: &SimParams,
    integrator: Integrator,
    head: &Affine3A,
    vertex_points: Option<usize>,
) -> Result<(Box<dyn Engine>, BackendInfo)> {
    let device = dev.adapter_name();
    let g = crate::gpu::GpuBackend::new(dev, groom, p, integrator, head, vertex_points)?;
    let info = BackendInfo {
        backend: Backend::GPU,
        device,
        fallback_reason: String::new(),
    };
    Ok((Box::new(g), info))
}
