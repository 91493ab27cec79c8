//! The GPU backend: the simulation state lives in device buffers and a step is one command
//! buffer of compute passes; nothing returns to the host unless it asks (an explicit
//! readback, blocking or one frame behind). One concern per file: creation and the backend's
//! state here, `kernels` (hair kernels from the pass list), `water`, `encode` (the step's
//! command buffers), `stamps` (GPU time per stage), `share` (the host's Vulkan), `readback`,
//! `blend` (fixed steps' output blend), `sdf` (SDF colliders), and `engine` (the seam).

mod blend;
mod bridges;
mod encode;
mod engine;
mod followers;
mod held;
mod kernels;
mod piles;
mod reactions;
mod readback;
mod roots;
mod sample;
mod sdf;
mod share;
mod stamps;
mod volume;
mod water;

use super::buffers::{self as b, Params, PointGpu, StateGpu, STORAGE};
use super::device::GpuDevice;
use super::pipelines::{self as pl, SceneConsts, Slot};
use crate::error::{Error, Result};
use crate::groom::Groom;
use crate::params::{Integrator, SimParams};
use crate::physics::bdf2::Bdf2Clock;
use crate::physics::roots::RootFrame;
use crate::plan::{has_bend, pass_list, Pass, WaterDomain};
use bridges::BridgesGpu;
use glam::{Affine3A, Vec3};
use held::HeldGpu;
use kernels::HairKernels;
use readback::Staging;
use share::WaterShare;
use stamps::PassStamps;
use std::sync::atomic::Ordering;
use water::{WaterGpu, WATER_ENTRIES};

/// Longest strand the GPU's implicit solve takes. One invocation solves one strand with its
/// banded system in private memory, about 168 bytes per point: 64 points need 10.75 KiB, and
/// NVIDIA's driver (H100, 580.159) loses the device at 96 points (16 KiB).
pub const MAX_IMPLICIT_POINTS: usize = 64;

/// The implicit solve's strand table (each strand's first point) and, for BDF2, its history
/// (each point's state at the last substep's start, written before it is read): the group's
/// layout and bind group.
fn strand_table(
    dev: &GpuDevice,
    strand_first: &[u32],
    bdf2: bool,
    state_bytes: u64,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let d = &dev.device;
    let buf = b::buffer(d, "strand_first", strand_first.len() as u64 * 4, STORAGE);
    dev.queue.write_buffer(&buf, 0, bytemuck::cast_slice(strand_first));
    if bdf2 {
        let history = b::buffer(d, "bdf2_history", state_bytes, STORAGE);
        let layout = pl::layout(d, "strands", &[Slot::Read, Slot::ReadWrite]);
        let bg = pl::bind(d, "strands", &layout, &[&buf, &history], None);
        (layout, bg)
    } else {
        let layout = pl::layout(d, "strands", &[Slot::Read]);
        let bg = pl::bind(d, "strands", &layout, &[&buf], None);
        (layout, bg)
    }
}

/// What the last status read found.
#[derive(Clone, Copy, Debug, Default)]
pub struct Status {
    /// Largest point speed in the step, m/s.
    pub max_speed: f32,
    /// First non-finite point (host order), if a step failed.
    pub failed_point: Option<u32>,
    /// Whether a water particle became non-finite.
    pub water_failed: bool,
    /// Particles held.
    pub particles: u32,
}

/// The GPU backend's state.
#[derive(Debug)]
pub struct GpuBackend {
    params: SimParams,
    /// The wind this step, m/s.
    pub(super) wind: Vec3,
    consts: SceneConsts,
    integrator: Integrator,
    /// BDF2's clock: which frames keep the history (the CPU backend holds the same).
    bdf2: Bdf2Clock,
    points: u32,
    /// Points and strands the hair passes run over: all, or the first guides a lower
    /// simulated fraction keeps (`followers.rs`).
    active_points: u32,
    active_strands: u32,
    /// The largest share of eq. 2's pull times inverse mass of any hair point (the stability
    /// limit's bound, `physics/pull_limit.rs`).
    pull_weight_max: f32,
    strand_first: Vec<u32>,
    /// A guide groom's bundle per point (`physics/bundles.rs`; empty otherwise), written into
    /// the water's absorption scratch ([`GpuBackend::write_bundles`]).
    bundle: Vec<f32>,
    rest_local: Vec<Vec3>,
    bend: bool,
    n_sub: usize,
    sub_stride: u64,
    params_buf: wgpu::Buffer,
    sub_buf: wgpu::Buffer,
    points_buf: wgpu::Buffer,
    state: [wgpu::Buffer; 2],
    status: wgpu::Buffer,
    vertices: wgpu::Buffer,
    hair_layout: wgpu::BindGroupLayout,
    /// Hair bind groups: [in = A, out = B], [in = B, out = A].
    hair_bg: [wgpu::BindGroup; 2],
    dry_hair: HairKernels,
    /// The strand table's (and BDF2's history's) layout and bind group (implicit Euler and
    /// BDF2 only).
    strands_layout: Option<wgpu::BindGroupLayout>,
    strands_bg: Option<wgpu::BindGroup>,
    /// Whether the strand table carries BDF2's history.
    strands_history: bool,
    output: wgpu::ComputePipeline,
    output_bg: [wgpu::BindGroup; 2],
    /// Fixed steps' output blend (once a state is kept).
    blend: Option<blend::OutputBlend>,
    /// Guides and followers' output (scenes with guides only).
    followers: Option<followers::FollowersGpu>,
    /// SDF colliders (scenes with SDFs only).
    sdf: Option<sdf::SdfColliders>,
    /// Skinned roots (scenes with them only).
    roots: Option<roots::SkinnedRoots>,
    /// Hair-hair volume (scenes with it only).
    volume: Option<volume::VolumeGpu>,
    cur: usize,
    /// Held water (scenes with `SimParams::held_water` on).
    held: Option<HeldGpu>,
    /// Liquid bridges (scenes with held water and `bridge_tension > 0`).
    bridges: Option<BridgesGpu>,
    /// Particles the host added since create or reset (held water's ledger).
    particles_added: u64,
    /// Water of the particles the host cleared since create or reset, quanta.
    left_cleared: u64,
    water: Option<WaterGpu>,
    /// Host-shared device only, once the host asks for the water as Vulkan buffers.
    water_share: Option<WaterShare>,
    /// Where particles are culled (head space).
    domain: WaterDomain,
    staging: Vec<Staging>,
    /// Host-shared device only: each step's status block, read back without waiting (two
    /// slots), so a failed step is reported though the host never reads through us.
    status_ring: Vec<Staging>,
    frame: u64,
    last: Status,
    /// The error budget's sampled points, copied every step (only under a budget).
    sample: Option<sample::Sample>,
    /// Whether the vertex buffer holds the current state.
    vertices_current: bool,
    /// GPU timestamps around each step's compute pass (only once asked for).
    timing: Option<Timing>,
    /// GPU time per stage, once a host switches it on ([`GpuBackend::time_passes`]).
    stamps: Option<PassStamps>,
    /// Head transform per substep, and their upload bytes (reused every step).
    heads: Vec<Affine3A>,
    sub_bytes: Vec<u8>,
    /// The analytic colliders' own frames (empty where they follow the head).
    pub(super) collider_frames: crate::physics::collide::ColliderFrames,
    /// Whether the encoder being filled writes the vertex buffer (the host's ready signal).
    wrote_vertices: bool,
    /// Last, so that every buffer and pipeline above is released before the device.
    dev: GpuDevice,
}

/// Timestamp queries around the step's compute pass, resolved into a small buffer.
#[derive(Debug)]
pub(super) struct Timing {
    pub(super) queries: wgpu::QuerySet,
    pub(super) resolve: wgpu::Buffer,
    pub(super) period_ns: f32,
}

impl GpuBackend {
    /// Uploads the groom and builds the dry pipelines. `integrator` must be symplectic Euler.
    pub fn new(
        dev: GpuDevice,
        groom: &Groom,
        params: &SimParams,
        integrator: Integrator,
        head: &Affine3A,
        vertex_points: Option<usize>,
    ) -> Result<Self> {
        params.held_water.check_masses(groom.masses())?;
        if integrator == Integrator::XPBD {
            return Err(Error::Unsupported(format!(
                "the GPU backend runs symplectic Euler, implicit Euler and BDF2; {integrator:?} runs on the CPU backend"
            )));
        }
        if integrator.is_implicit() && groom.max_strand_points() > MAX_IMPLICIT_POINTS {
            return Err(Error::Unsupported(format!(
                "the GPU's implicit solve takes strands of up to {MAX_IMPLICIT_POINTS} points (this groom has {}); \
                 longer strands run implicit Euler on the CPU backend",
                groom.max_strand_points()
            )));
        }
        let d = &dev.device;
        let points = groom.point_count() as u32;
        let strands = groom.strand_count() as u32;
        let state_bytes = points as u64 * 32;
        let stride = params.attributes.stride() as u64;
        // The largest per-point buffer must fit one binding (wgpu refuses the bind group
        // otherwise, with a validation error instead of a reason).
        let per_point = [
            ("point records", std::mem::size_of::<PointGpu>() as u64),
            ("state", 32),
            ("vertices", stride * 4),
            (
                "bridge records",
                if params.held_water.bridges() {
                    b::bridge_words::PER_POINT as u64 * 4
                } else {
                    0
                },
            ),
        ];
        // With followers the groom is a guide groom: its strands may stand for more than
        // themselves (held water's bundles).
        let guides = vertex_points.is_some();
        let vertex_points = vertex_points.map_or(points as u64, |v| v as u64);
        let (what, bytes) = per_point
            .iter()
            .map(|&(what, b)| {
                (
                    what,
                    b * if what == "vertices" {
                        vertex_points
                    } else {
                        points as u64
                    },
                )
            })
            .max_by_key(|p| p.1)
            .expect("four buffers");
        // The bridges' bucket table is scanned one workgroup per block of buckets, in one
        // dispatch row.
        let bucket_blocks = (2 * points as u64).next_power_of_two() / b::SCAN_BLOCK as u64;
        if params.held_water.bridges() && bucket_blocks > dev.limits.max_compute_workgroups_per_dimension as u64 {
            return Err(Error::Capacity(format!(
                "liquid bridges on the GPU take up to {} points (this groom has {points}); the CPU backend has no such limit",
                dev.limits.max_compute_workgroups_per_dimension as u64 * b::SCAN_BLOCK as u64 / 2
            )));
        }
        if bytes > dev.limits.max_storage_buffer_binding_size {
            return Err(Error::Capacity(format!(
                "{points} points need {bytes} bytes of {what}; {} allows {} per buffer (the CPU backend has no such limit)",
                dev.info.name, dev.limits.max_storage_buffer_binding_size
            )));
        }
        let pos = groom.positions();
        let springs = crate::plan::point_springs(groom, params);
        let mut pts = Vec::with_capacity(points as usize);
        for s in 0..groom.strand_count() {
            let r = groom.strand_range(s);
            let (first, last) = (r.start as u32, r.end as u32 - 1);
            for i in r {
                let free = !groom.pinned()[i];
                let sp = &springs[i];
                pts.push(PointGpu {
                    rest: pos[i].to_array(),
                    inv_mass: if free { 1.0 / groom.masses()[i] } else { 0.0 },
                    rest_stretch: sp.rest[0],
                    rest_bend: sp.rest[1],
                    first,
                    last,
                    stretch_k: sp.stretch.stiffness,
                    stretch_c: sp.stretch.damping,
                    bend_k: sp.bend.stiffness,
                    bend_c: sp.bend.damping,
                });
            }
        }
        let rows = groom.max_strand_points();
        let bend = has_bend(params, rows);
        let consts = SceneConsts {
            axial: params.damping_model == crate::DampingModel::AXIAL,
            colliders: params.colliders.len() as u32,
            bend,
            max_points: rows as u32,
            iterations: params.solver_iterations,
            bdf2: integrator == Integrator::BDF2,
            roots: params.skinned_roots,
            atomic64: dev.atomic64,
            gathered: super::device::gathers_reactions(),
            bundle_points: if guides { points } else { 0 },
        };
        let n_sub = params.substeps as usize;
        let align = dev.limits.min_uniform_buffer_offset_alignment as u64;
        let collider_bytes = std::mem::size_of::<super::buffers::ColliderGpu>() as u64;
        let sub_size = b::SUBSTEP_HEAD_BYTES as u64 + collider_bytes * consts.colliders.max(1) as u64;
        let sub_stride = sub_size.next_multiple_of(align);
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let params_buf = b::buffer(d, "params", std::mem::size_of::<Params>() as u64, uniform);
        // Room for the most substeps an error budget may choose (`set_substeps`).
        let most_sub = if params.tolerance > 0.0 {
            n_sub.max(params.max_substeps as usize)
        } else {
            n_sub
        };
        let sub_buf = b::buffer(d, "substeps", sub_stride * most_sub as u64, uniform);
        let points_buf = b::buffer(d, "points", std::mem::size_of_val(pts.as_slice()) as u64, STORAGE);
        dev.queue.write_buffer(&points_buf, 0, bytemuck::cast_slice(&pts));
        let state = [
            b::buffer(d, "state_a", state_bytes, STORAGE),
            b::buffer(d, "state_b", state_bytes, STORAGE),
        ];
        let status = b::buffer(d, "status", 16, STORAGE);
        let vertices = b::buffer(
            d,
            "vertices",
            vertex_points * stride * 4,
            STORAGE | wgpu::BufferUsages::VERTEX,
        );
        let hair_layout = pl::layout(
            d,
            "hair",
            &[
                Slot::Uniform,
                Slot::UniformDynamic,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
                Slot::ReadWrite,
            ],
        );
        let held = params.held_water.enabled.then(|| {
            let mut h = HeldGpu::new(d, &dev.queue, consts, &pts, groom.masses(), params.held_water);
            h.bind(d, &params_buf, &points_buf, &state);
            h
        });
        // With held water the hair kernels read the point records with the water's mass.
        let hair_points = held.as_ref().map_or(&points_buf, |h| &h.points_wet);
        let bridges = held
            .as_ref()
            .filter(|_| params.held_water.bridges())
            .map(|h| BridgesGpu::new(d, consts, points, &params_buf, &h.points_wet, h.bridge_inputs(), &state));
        let mk_hair = |i: usize| {
            pl::bind(
                d,
                "hair",
                &hair_layout,
                &[&params_buf, &sub_buf, hair_points, &state[i], &state[1 - i], &status],
                Some((1, sub_size)),
            )
        };
        let hair_bg = [mk_hair(0), mk_hair(1)];
        let out_layout = pl::layout(
            d,
            "output",
            &[Slot::Uniform, Slot::Read, Slot::Read, Slot::Read, Slot::ReadWrite],
        );
        let mk_out = |i: usize| {
            pl::bind(
                d,
                "output",
                &out_layout,
                &[&params_buf, &points_buf, &state[i], &status, &vertices],
                None,
            )
        };
        let output_bg = [mk_out(0), mk_out(1)];
        let dry_passes = pass_list(params, integrator, bend, false);
        let strand_table = integrator
            .is_implicit()
            .then(|| strand_table(&dev, &groom.strand_first, integrator == Integrator::BDF2, state_bytes));
        let dry_hair = HairKernels::new(
            d,
            consts,
            &dry_passes,
            &hair_layout,
            None,
            strand_table.as_ref().map(|s| &s.0),
            bridges.as_ref().map(|b| &b.cohesion_layout),
        );
        let sdf = if params.sdfs.is_empty() {
            None
        } else {
            let inputs = sdf::SdfInputs {
                params: &params_buf,
                points: hair_points,
                state: &state,
                most_sub,
                align,
                max_storage: dev.limits.max_storage_buffer_binding_size,
            };
            Some(sdf::SdfColliders::new(d, &dev.queue, consts, &params.sdfs, inputs)?)
        };
        let roots = params.skinned_roots.then(|| {
            let inputs = roots::RootsInputs {
                rest: pos,
                strand_first: &groom.strand_first,
                pinned: groom.pinned(),
                points: hair_points,
                state: &state,
                most_sub,
                align,
            };
            roots::SkinnedRoots::new(d, &dev.queue, consts, inputs)
        });
        let volume = if params.volume.enabled {
            let max = dev.limits.max_storage_buffer_binding_size;
            Some(volume::VolumeGpu::new(
                d,
                consts,
                groom,
                &params.volume,
                hair_points,
                &state,
                max,
            )?)
        } else {
            None
        };
        let out_mod = pl::module(d, "output", &pl::output_source(consts));
        let output = pl::pipelines(d, &out_mod, &[&out_layout], &["write_vertices"]).remove(0);
        let mut be = GpuBackend {
            dev,
            params: params.clone(),
            consts,
            integrator,
            bdf2: Bdf2Clock::default(),
            points,
            active_points: points,
            active_strands: strands,
            pull_weight_max: crate::plan::water::pull_weight_max(params, groom),
            strand_first: groom.strand_first.clone(),
            bundle: Vec::new(),
            rest_local: pos.to_vec(),
            bend,
            n_sub,
            sub_stride,
            params_buf,
            sub_buf,
            points_buf,
            state,
            status,
            vertices,
            hair_layout,
            hair_bg,
            dry_hair,
            strands_layout: strand_table.as_ref().map(|s| s.0.clone()),
            strands_bg: strand_table.map(|s| s.1),
            strands_history: integrator == Integrator::BDF2,
            output,
            output_bg,
            blend: None,
            followers: None,
            sdf,
            roots,
            volume,
            cur: 0,
            held,
            bridges,
            particles_added: 0,
            left_cleared: 0,
            water: None,
            water_share: None,
            domain: WaterDomain::new(groom, params),
            wind: params.wind.velocity,
            staging: Vec::new(),
            status_ring: Vec::new(),
            frame: 0,
            last: Status::default(),
            vertices_current: false,
            sample: None,
            timing: None,
            stamps: None,
            heads: vec![*head; n_sub],
            sub_bytes: vec![0; sub_stride as usize * n_sub],
            collider_frames: crate::physics::collide::ColliderFrames::new(&params.collider_frames),
            wrote_vertices: false,
        };
        // The vertex output reads its layout (stride, attribute offsets) from the step
        // parameters: write them now, so vertices read before the first step are the rest
        // pose and not zeros (the step rewrites them with its own time step).
        if be.held.as_ref().is_some_and(|h| h.drips()) {
            // Drops are made in the step: the particle buffers come now, as on the CPU.
            let w = be.create_water()?;
            let d = &be.dev.device;
            let h = be.held.as_mut().expect("checked");
            h.bind_drip(d, &w.particles, &w.state);
            h.bind_absorb(d, &w.particles, &w.grid, &w.absorb, &be.state);
            be.water = Some(w);
        }
        be.write_params(1.0 / 60.0, 0, head);
        be.reset(head);
        be.dev.wait()?;
        Ok(be)
    }

    /// The adapter in use.
    pub fn adapter_name(&self) -> String {
        self.dev.adapter_name()
    }

    /// The integrator in use.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Hair points.
    pub fn points(&self) -> usize {
        self.points as usize
    }

    pub(super) fn wet(&self) -> bool {
        self.water.as_ref().is_some_and(|w| w.bound > 0 || w.pending > 0)
    }

    /// The passes the next step runs, in order: the same list as the CPU's for this scene.
    pub fn passes(&self) -> Vec<Pass> {
        pass_list(&self.params, self.integrator, self.bend, self.wet())
    }

    /// The compute entry points one step dispatches, in order (per substep, then per step).
    pub fn dispatches(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        let wet = self.wet();
        let (held_before, held_after) = self.held.as_ref().map(|h| h.dispatches()).unwrap_or_default();
        if self.water.as_ref().is_some_and(|w| w.pending > 0) {
            v.push("water_append");
        }
        v.extend(held_before);
        if self.bridges.is_some() {
            v.extend_from_slice(&bridges::BRIDGE_ENTRIES);
        }
        if self.volume.is_some() {
            v.extend_from_slice(&["volume_spread", "volume_respond"]);
        }
        if wet {
            v.extend_from_slice(&WATER_ENTRIES[1..8]);
        }
        let k = if wet {
            self.water.as_ref().map(|w| &w.wet_hair)
        } else {
            None
        }
        .unwrap_or(&self.dry_hair);
        if self.roots.is_some() {
            v.push("pin_roots");
        }
        if k.cohesion.is_some() {
            v.push("cohesion");
        }
        if k.forces.is_some() {
            v.push("hair_forces");
        }
        v.push(if k.implicit { "implicit_solve" } else { "hair_substep" });
        if self.sdf.is_some() {
            v.push("hair_sdf");
        }
        if wet {
            v.extend_from_slice(self.held.as_ref().map_or(&[][..], |h| h.absorb_dispatches()));
            v.push("water_integrate");
            if self.sdf.is_some() {
                v.push("water_sdf");
            }
        }
        v.extend(held_after);
        if wet {
            v.extend_from_slice(&["water_cull", "water_cull_finish"]);
        }
        v
    }

    /// Every device buffer with its size in bytes.
    pub fn buffers(&self) -> Vec<(&'static str, usize)> {
        let mut v = vec![
            ("params", self.params_buf.size() as usize),
            ("substeps", self.sub_buf.size() as usize),
            ("points", self.points_buf.size() as usize),
            ("state", 2 * self.state[0].size() as usize),
            ("status", self.status.size() as usize),
            ("vertices", self.vertices.size() as usize),
        ];
        if let Some(w) = &self.water {
            v.push(("water_particles", 2 * w.particles[0].size() as usize));
            v.push(("water_reactions", w.force.size() as usize));
            if let Some(r) = &w.reactions {
                v.push(("water_reaction_order", r.order_bytes()));
            }
            v.push((
                "water_grid",
                (w.grid.size() + w.grid_count.size() + w.state.size() + w.dispatch.size()) as usize,
            ));
            v.push(("water_incoming", w.incoming.size() as usize));
            if let Some(p) = &w.piles {
                v.push(("water_piles", p.bytes() as usize));
            }
        }
        if let Some(h) = &self.held {
            v.push(("held_water", h.bytes()));
        }
        if let Some(br) = &self.bridges {
            v.push(("bridges", br.bytes()));
        }
        if let Some(ws) = &self.water_share {
            v.push(("water_shared", (ws.vertices.size() + ws.draw.size()) as usize));
        }
        if !self.staging.is_empty() {
            v.push(("readback", self.staging.iter().map(|s| s.buf.size() as usize).sum()));
        }
        if let Some(bl) = &self.blend {
            v.push(("output_from", bl.bytes()));
        }
        if let Some(fg) = &self.followers {
            v.push(("followers", fg.bytes()));
        }
        if let Some(sd) = &self.sdf {
            v.push(("sdf", sd.bytes()));
        }
        if let Some(r) = &self.roots {
            v.push(("roots", r.bytes()));
        }
        if let Some(vol) = &self.volume {
            v.push(("volume", vol.bytes()));
        }
        v
    }

    /// Back to the rest pose at `head`, dry, no water, status cleared.
    pub fn reset(&mut self, head: &Affine3A) {
        let st: Vec<StateGpu> = self
            .rest_local
            .iter()
            .map(|p| StateGpu {
                x: head.transform_point3(*p).extend(0.0).to_array(),
                v: [0.0; 4],
            })
            .collect();
        self.dev
            .queue
            .write_buffer(&self.state[0], 0, bytemuck::cast_slice(&st));
        self.cur = 0;
        self.bdf2 = Bdf2Clock::default();
        if let Some(bl) = &mut self.blend {
            bl.on = false;
        }
        self.dev
            .queue
            .write_buffer(&self.status, 0, bytemuck::cast_slice(&[0u32, 0, u32::MAX, 0])); // no failed point
        if let Some(w) = &mut self.water {
            self.dev.queue.write_buffer(
                &w.state,
                0,
                bytemuck::cast_slice(&[0u32; b::water_state::WORDS as usize]),
            );
            w.bound = 0;
            w.pending = 0;
            w.removed = 0;
        }
        if let Some(h) = &self.held {
            let mut enc = self.dev.device.create_command_encoder(&Default::default());
            h.reset(&mut enc);
            if let Some(br) = &mut self.bridges {
                br.reset(&mut enc);
            }
            self.dev.submit(enc.finish(), false);
        }
        self.particles_added = 0;
        self.left_cleared = 0;
        self.last = Status::default();
        for s in self.staging.iter_mut().chain(self.status_ring.iter_mut()) {
            if s.frame.take().is_some() {
                self.dev.device.poll(wgpu::PollType::wait_indefinitely()).ok();
                s.buf.unmap();
                s.ready.store(false, Ordering::Release);
            }
        }
        self.reset_sample();
        self.vertices_current = false;
    }

    /// Starts timing each step on the GPU with timestamp queries. Returns false when the
    /// adapter has none (then only wall-clock timing is possible).
    pub fn enable_timing(&mut self) -> bool {
        if !self.dev.timestamps {
            return false;
        }
        if self.timing.is_none() {
            let d = &self.dev.device;
            self.timing = Some(Timing {
                queries: d.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("step timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolve: b::buffer(
                    d,
                    "timestamps",
                    16,
                    wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                ),
                period_ns: self.dev.queue.get_timestamp_period(),
            });
        }
        true
    }

    /// Moves the SDF colliders from `from` to `to` over the next step.
    pub fn place_sdfs(&mut self, from: &[Affine3A], to: &[Affine3A]) {
        if let Some(sd) = &mut self.sdf {
            sd.place(from, to);
        }
    }

    /// Moves the skinned roots from `from` to `to` (one per host strand) over the next step.
    pub fn place_roots(&mut self, from: &[RootFrame], to: &[RootFrame]) {
        if let Some(r) = &mut self.roots {
            r.place(&self.dev.queue, from, to);
        }
    }

    /// Carries host strands `strands` rigidly from root frames `from` to `to` now, at rest
    /// (a submission of its own), and starts BDF2 again.
    pub fn carry_strands(&mut self, strands: &[u32], from: &[RootFrame], to: &[RootFrame]) -> Result<()> {
        self.dev.check()?;
        let Some(r) = &mut self.roots else {
            return Ok(());
        };
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        r.encode_carry(&self.dev.queue, &mut enc, self.cur, strands, from, to);
        self.dev.submit(enc.finish(), false);
        self.bdf2 = Bdf2Clock::default();
        self.vertices_current = false;
        Ok(())
    }

    /// Runs `n` substeps per step from the next step on (at most what `substeps` has room
    /// for: the error budget's cap).
    pub fn set_substeps(&mut self, n: u32) {
        let n_sub = n as usize;
        debug_assert!(self.sub_buf.size() >= self.sub_stride * n as u64);
        self.n_sub = n_sub;
        self.params.substeps = n;
        self.heads.resize(n_sub, Affine3A::IDENTITY);
        self.sub_bytes.resize(self.sub_stride as usize * n_sub, 0);
        if self.stamps.is_some() {
            self.stamps = Some(PassStamps::new(&self.dev.device, &self.dev.queue, n_sub));
        }
    }

    /// Switches per-stage GPU timing on (totals from zero) or off. Returns false where the
    /// adapter cannot write timestamps inside a compute pass. On, each step waits for the GPU
    /// to read its stamps back.
    pub fn time_passes(&mut self, on: bool) -> bool {
        if !self.dev.pass_timestamps {
            return false;
        }
        self.stamps = on.then(|| PassStamps::new(&self.dev.device, &self.dev.queue, self.n_sub));
        true
    }

    /// Per-stage GPU time since [`GpuBackend::time_passes`] switched it on, in step order.
    pub fn pass_times(&self) -> Vec<crate::engine::PassTime> {
        self.stamps.as_ref().map_or_else(Vec::new, |s| s.clock.times())
    }

    /// GPU time of the last step's compute pass, ms (waits for it), once timing is enabled.
    pub fn last_step_gpu_ms(&self) -> Option<Result<f64>> {
        let t = self.timing.as_ref()?;
        Some(self.read_buffers(&[(&t.resolve, 16)], None).map(|bytes| {
            let q: &[u64] = bytemuck::cast_slice(&bytes[..16]);
            q[1].saturating_sub(q[0]) as f64 * t.period_ns as f64 * 1e-6
        }))
    }

    /// Makes the device fail as a lost device would (tests of the error path).
    pub fn lose_device(&self) {
        self.dev.lose();
    }
}

impl Drop for GpuBackend {
    fn drop(&mut self) {
        // Let submitted work finish before buffers go (wgpu keeps them alive, but a host that
        // destroys and recreates expects the device idle).
        let _ = self.dev.device.poll(wgpu::PollType::wait_indefinitely());
    }
}
