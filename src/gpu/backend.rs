//! The GPU backend: the simulation state lives in device buffers and a step is one command
//! buffer of compute passes; nothing returns to the host unless it asks (an explicit
//! readback, blocking or one frame behind).

use super::buffers::{self as b, groups, ColliderGpu, Params, PointGpu, StateGpu, STORAGE};
use super::device::GpuDevice;
use super::pipelines::{self as pl, SceneConsts, Slot};
use crate::cpu::step::{pass_list, Pass};
use crate::error::{Error, Result};
use crate::groom::Groom;
use crate::params::{Integrator, Readback, SimParams, VertexAttributes};
use crate::physics::collide::Placed;
use crate::physics::grid::MAX_CELLS;
use glam::{Affine3A, Vec3};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Bytes of the status block at the start of every readback: hair status then water state.
const STATUS_BYTES: u64 = 32;

/// Water buffers and pipelines, created at the first `add_water`.
#[derive(Debug)]
struct WaterGpu {
    particles: [wgpu::Buffer; 2],
    force: wgpu::Buffer,
    grid_count: wgpu::Buffer,
    grid: wgpu::Buffer,
    state: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    incoming: wgpu::Buffer,
    /// Build bind groups: [cur = A, other = B], [cur = B, other = A].
    build_bg: [wgpu::BindGroup; 2],
    /// The indirect-dispatch buffer as storage (grid_setup only).
    dispatch_bg: wgpu::BindGroup,
    /// Hair-side bind groups: sorted = B (when cur = A), sorted = A.
    hair_bg: [wgpu::BindGroup; 2],
    /// Pipelines by entry point (see `WATER_ENTRIES`).
    pipes: Vec<wgpu::ComputePipeline>,
    /// The hair kernels of the wet scene.
    wet_hair: HairKernels,
    /// Which particle buffer holds the particles.
    cur: usize,
    /// An upper bound on the particles held (exact after a status read).
    bound: u32,
    /// Particles uploaded, waiting for the next step's append.
    pending: u32,
    /// Removed since create or reset, as of the last status read.
    removed: u64,
}

/// Host-shared devices whose host draws the particles (made at its first ask): their
/// positions and the indirect draw's arguments, written with the vertices in the submission
/// that waits for the host's release.
#[derive(Debug)]
struct WaterShare {
    vertices: wgpu::Buffer,
    draw: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    pipe: wgpu::ComputePipeline,
    /// By `WaterGpu::cur`, once the particles exist.
    bg: Option<[wgpu::BindGroup; 2]>,
}

impl WaterGpu {
    /// Encodes pass water_grid over the held particles: bounds, setup, count, prefix sum and,
    /// with `scatter`, the scatter into grid order (without it the counts stay for a test).
    fn encode_grid(&self, pass: &mut wgpu::ComputePass, scatter: bool) {
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

/// The hair kernels of one scene variant (dry or wet).
#[derive(Debug)]
struct HairKernels {
    /// hair_forces: implicit Euler's explicit forces (only with drag or water).
    forces: Option<wgpu::ComputePipeline>,
    /// hair_substep (symplectic Euler) or implicit_solve (one invocation per strand).
    solve: wgpu::ComputePipeline,
    /// Whether `solve` is implicit_solve.
    implicit: bool,
    /// water_integrate (wet only).
    water: Option<wgpu::ComputePipeline>,
}

impl HairKernels {
    /// Compiles the hair module for `passes`. `water`: the water group's layout when wet;
    /// `strands`: the strand table's layout for implicit Euler.
    fn new(
        d: &wgpu::Device,
        consts: SceneConsts,
        passes: &[Pass],
        hair: &wgpu::BindGroupLayout,
        water: Option<&wgpu::BindGroupLayout>,
        strands: Option<&wgpu::BindGroupLayout>,
    ) -> HairKernels {
        let implicit = passes.contains(&Pass::ImplicitSolve);
        let module = pl::module(d, "hair", &pl::hair_source(consts, passes));
        let main: Vec<Option<&wgpu::BindGroupLayout>> = vec![Some(hair), water];
        let one = |layouts: &[Option<&wgpu::BindGroupLayout>], e: &str| {
            pl::pipelines_sparse(d, &module, layouts, &[e]).remove(0)
        };
        HairKernels {
            forces: (implicit && pl::has_forces(passes)).then(|| one(&main, "hair_forces")),
            solve: if implicit {
                one(&[Some(hair), None, strands], "implicit_solve")
            } else {
                one(&main, "hair_substep")
            },
            implicit,
            water: water.map(|_| one(&main, "water_integrate")),
        }
    }

    /// Encodes one substep's hair kernels (not water_integrate).
    #[allow(clippy::too_many_arguments)]
    fn encode(
        &self,
        pass: &mut wgpu::ComputePass,
        hair: &wgpu::BindGroup,
        off: &[u32],
        water: Option<&wgpu::BindGroup>,
        strands: Option<&wgpu::BindGroup>,
        points: u32,
        n_strands: u32,
    ) {
        let (px, py) = groups(points);
        pass.set_bind_group(0, hair, off);
        if let Some(f) = &self.forces {
            pass.set_pipeline(f);
            if let Some(w) = water {
                pass.set_bind_group(1, w, &[]);
            }
            pass.dispatch_workgroups(px, py, 1);
        }
        pass.set_pipeline(&self.solve);
        if self.implicit {
            if let Some(s) = strands {
                pass.set_bind_group(2, s, &[]);
            }
            let (sx, sy) = groups(n_strands);
            pass.dispatch_workgroups(sx, sy, 1);
        } else {
            if let Some(w) = water {
                pass.set_bind_group(1, w, &[]);
            }
            pass.dispatch_workgroups(px, py, 1);
        }
    }
}

const WATER_ENTRIES: [&str; 10] = [
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

/// Longest strand the GPU's implicit solve takes. One invocation solves one strand with its
/// banded system in private memory, about 168 bytes per point: 64 points need 10.75 KiB, and
/// NVIDIA's driver (H100, 580.159) loses the device at 96 points (16 KiB).
pub const MAX_IMPLICIT_POINTS: usize = 64;

/// One staging buffer of the readback ring.
#[derive(Debug)]
struct Staging {
    buf: wgpu::Buffer,
    /// The step whose vertices it holds (mapped or being mapped), if any.
    frame: Option<u64>,
    ready: Arc<AtomicBool>,
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
    consts: SceneConsts,
    integrator: Integrator,
    points: u32,
    strands: u32,
    strand_first: Vec<u32>,
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
    /// The strand table's layout and bind group (implicit Euler only).
    strands_layout: Option<wgpu::BindGroupLayout>,
    strands_bg: Option<wgpu::BindGroup>,
    output: wgpu::ComputePipeline,
    output_bg: [wgpu::BindGroup; 2],
    cur: usize,
    water: Option<WaterGpu>,
    /// Host-shared device only, once the host asks for the water as Vulkan buffers.
    water_share: Option<WaterShare>,
    water_center_local: Vec3,
    water_radius: f32,
    staging: Vec<Staging>,
    /// Host-shared device only: each step's status block, read back without waiting (two
    /// slots), so a failed step is reported though the host never reads through us.
    status_ring: Vec<Staging>,
    frame: u64,
    last: Status,
    /// Whether the vertex buffer holds the current state.
    vertices_current: bool,
    /// GPU timestamps around each step's compute pass (only once asked for).
    timing: Option<Timing>,
    /// Head transform per substep, and their upload bytes (reused every step).
    heads: Vec<Affine3A>,
    sub_bytes: Vec<u8>,
    /// Whether the encoder being filled writes the vertex buffer (the host's ready signal).
    wrote_vertices: bool,
    /// Last, so that every buffer and pipeline above is released before the device.
    dev: GpuDevice,
}

/// Timestamp queries around the step's compute pass, resolved into a small buffer.
#[derive(Debug)]
struct Timing {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    period_ns: f32,
}

impl GpuBackend {
    /// Uploads the groom and builds the dry pipelines. `integrator` must be symplectic Euler.
    pub fn new(
        dev: GpuDevice,
        groom: &Groom,
        params: &SimParams,
        integrator: Integrator,
        head: &Affine3A,
    ) -> Result<Self> {
        if !matches!(integrator, Integrator::SymplecticEuler | Integrator::ImplicitEuler) {
            return Err(Error::Unsupported(format!(
                "the GPU backend runs symplectic and implicit Euler; {integrator:?} runs on the CPU backend"
            )));
        }
        if integrator == Integrator::ImplicitEuler && groom.max_strand_points() > MAX_IMPLICIT_POINTS {
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
        if state_bytes > dev.limits.max_storage_buffer_binding_size {
            return Err(Error::Capacity(format!(
                "{points} points need {state_bytes} bytes of state; {} allows {} per buffer",
                dev.info.name, dev.limits.max_storage_buffer_binding_size
            )));
        }
        let pos = groom.positions();
        let mut pts = Vec::with_capacity(points as usize);
        for s in 0..groom.strand_count() {
            let r = groom.strand_range(s);
            let (first, last) = (r.start as u32, r.end as u32 - 1);
            for i in r.clone() {
                let free = !groom.pinned()[i];
                pts.push(PointGpu {
                    rest: pos[i].to_array(),
                    inv_mass: if free { 1.0 / groom.masses()[i] } else { 0.0 },
                    rest_stretch: if i + 1 < r.end {
                        (pos[i + 1] - pos[i]).length()
                    } else {
                        0.0
                    },
                    rest_bend: if i + 2 < r.end {
                        (pos[i + 2] - pos[i]).length()
                    } else {
                        0.0
                    },
                    first,
                    last,
                });
            }
        }
        let rows = groom.max_strand_points();
        let bend = rows > 2 && (params.bend.stiffness > 0.0 || params.bend.damping > 0.0);
        let consts = SceneConsts {
            axial: params.damping_model == crate::DampingModel::Axial,
            colliders: params.colliders.len() as u32,
            bend,
            max_points: rows as u32,
            iterations: params.solver_iterations,
        };
        let n_sub = params.substeps as usize;
        let align = dev.limits.min_uniform_buffer_offset_alignment as u64;
        let sub_size = 64 + 32 * consts.colliders.max(1) as u64;
        let sub_stride = sub_size.next_multiple_of(align);
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let params_buf = b::buffer(d, "params", std::mem::size_of::<Params>() as u64, uniform);
        let sub_buf = b::buffer(d, "substeps", sub_stride * n_sub as u64, uniform);
        let points_buf = b::buffer(d, "points", points as u64 * 32, STORAGE);
        dev.queue.write_buffer(&points_buf, 0, bytemuck::cast_slice(&pts));
        let state = [
            b::buffer(d, "state_a", state_bytes, STORAGE),
            b::buffer(d, "state_b", state_bytes, STORAGE),
        ];
        let status = b::buffer(d, "status", 16, STORAGE);
        let vertices = b::buffer(
            d,
            "vertices",
            points as u64 * stride * 4,
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
        let mk_hair = |i: usize| {
            pl::bind(
                d,
                "hair",
                &hair_layout,
                &[&params_buf, &sub_buf, &points_buf, &state[i], &state[1 - i], &status],
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
        let strand_table = (integrator == Integrator::ImplicitEuler).then(|| {
            let buf = b::buffer(d, "strand_first", groom.strand_first.len() as u64 * 4, STORAGE);
            dev.queue
                .write_buffer(&buf, 0, bytemuck::cast_slice(&groom.strand_first));
            let layout = pl::layout(d, "strands", &[Slot::Read]);
            let bg = pl::bind(d, "strands", &layout, &[&buf], None);
            (layout, bg)
        });
        let dry_hair = HairKernels::new(
            d,
            consts,
            &dry_passes,
            &hair_layout,
            None,
            strand_table.as_ref().map(|s| &s.0),
        );
        let out_mod = pl::module(d, "output", &pl::output_source(consts));
        let output = pl::pipelines(d, &out_mod, &[&out_layout], &["write_vertices"]).remove(0);
        let (lo, hi) = groom.bounds();
        let water_radius = if params.water.domain_radius > 0.0 {
            params.water.domain_radius
        } else {
            0.5 * (hi - lo).length() + groom.max_strand_length()
        };
        let mut be = GpuBackend {
            dev,
            params: params.clone(),
            consts,
            integrator,
            points,
            strands,
            strand_first: groom.strand_first.clone(),
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
            output,
            output_bg,
            cur: 0,
            water: None,
            water_share: None,
            water_center_local: 0.5 * (lo + hi),
            water_radius,
            staging: Vec::new(),
            status_ring: Vec::new(),
            frame: 0,
            last: Status::default(),
            vertices_current: false,
            timing: None,
            heads: vec![*head; n_sub],
            sub_bytes: vec![0; sub_stride as usize * n_sub],
            wrote_vertices: false,
        };
        // The vertex output reads its layout (stride, attribute offsets) from the step
        // parameters: write them now, so vertices read before the first step are the rest
        // pose and not zeros (the step rewrites them with its own time step).
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

    fn wet(&self) -> bool {
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
        if self.water.as_ref().is_some_and(|w| w.pending > 0) {
            v.push("water_append");
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
        if k.forces.is_some() {
            v.push("hair_forces");
        }
        v.push(if k.implicit { "implicit_solve" } else { "hair_substep" });
        if wet {
            v.extend_from_slice(&["water_integrate", "water_cull", "water_cull_finish"]);
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
            v.push((
                "water_grid",
                (w.grid.size() + w.grid_count.size() + w.state.size() + w.dispatch.size()) as usize,
            ));
            v.push(("water_incoming", w.incoming.size() as usize));
        }
        if let Some(ws) = &self.water_share {
            v.push(("water_shared", (ws.vertices.size() + ws.draw.size()) as usize));
        }
        if !self.staging.is_empty() {
            v.push(("readback", self.staging.iter().map(|s| s.buf.size() as usize).sum()));
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
        self.dev
            .queue
            .write_buffer(&self.status, 0, bytemuck::cast_slice(&[0u32, 0, u32::MAX, 0]));
        if let Some(w) = &mut self.water {
            self.dev
                .queue
                .write_buffer(&w.state, 0, bytemuck::cast_slice(&[0u32; 4]));
            w.bound = 0;
            w.pending = 0;
            w.removed = 0;
        }
        self.last = Status::default();
        for s in self.staging.iter_mut().chain(self.status_ring.iter_mut()) {
            if s.frame.take().is_some() {
                self.dev.device.poll(wgpu::PollType::wait_indefinitely()).ok();
                s.buf.unmap();
                s.ready.store(false, Ordering::Release);
            }
        }
        self.vertices_current = false;
    }

    /// Uploads particles (they join at the next step); water buffers are created at the
    /// first call.
    pub fn add_water(&mut self, pos: &[Vec3], vel: &[Vec3]) -> Result<()> {
        crate::cpu::water::check_new_particles(pos, vel)?;
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
        let recs: Vec<StateGpu> = pos
            .iter()
            .enumerate()
            .map(|(i, p)| StateGpu {
                x: p.extend(0.0).to_array(),
                v: vel.get(i).copied().unwrap_or(Vec3::ZERO).extend(0.0).to_array(),
            })
            .collect();
        self.dev
            .queue
            .write_buffer(&w.incoming, w.pending as u64 * 32, bytemuck::cast_slice(&recs));
        w.pending += n;
        Ok(())
    }

    /// Removes every particle.
    pub fn clear_water(&mut self) {
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

    fn create_water(&self) -> Result<WaterGpu> {
        let d = &self.dev.device;
        let cap = self.params.water.capacity as u64;
        let particles = [
            b::buffer(d, "particles_a", cap * 32, STORAGE),
            b::buffer(d, "particles_b", cap * 32, STORAGE),
        ];
        let force = b::buffer(d, "water_force", cap * 16, STORAGE);
        let grid_count = b::buffer(d, "grid_count", (8 + MAX_CELLS as u64) * 4, STORAGE);
        let grid = b::buffer(d, "grid", (16 + MAX_CELLS as u64 + 1 + 256) * 4, STORAGE);
        let state = b::buffer(d, "water_state", 16, STORAGE);
        let dispatch = b::buffer(d, "grid_dispatch", 16, STORAGE | wgpu::BufferUsages::INDIRECT);
        // Particles added in one frame; the whole capacity at most.
        let incoming = b::buffer(d, "water_incoming", cap * 32, STORAGE);
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
        let hair_layout = pl::layout(d, "water hair", &[Slot::ReadWrite, Slot::ReadWrite, Slot::Read]);
        let mk_build = |i: usize| {
            pl::bind(
                d,
                "water build",
                &build_layout,
                &[
                    &self.params_buf,
                    &particles[i],
                    &particles[1 - i],
                    &force,
                    &grid_count,
                    &grid,
                    &state,
                    &incoming,
                ],
                None,
            )
        };
        let mk_hair = |i: usize| pl::bind(d, "water hair", &hair_layout, &[&particles[1 - i], &force, &grid], None);
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
        );
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
            pipes,
            wet_hair,
            cur: 0,
            bound: 0,
            pending: 0,
            removed: 0,
        })
    }

    fn write_params(&self, h: f32, incoming: u32, to: &Affine3A) {
        let p = &self.params;
        let a = p.attributes;
        let off = |bit| a.offset(bit).map_or(u32::MAX, |o| o as u32);
        let c = to.transform_point3(self.water_center_local);
        let rec = Params {
            h,
            inv_h: 1.0 / h,
            drag: p.air_drag,
            friction: p.friction,
            g: p.gravity.extend(0.0).to_array(),
            points: self.points,
            strands: self.strands,
            stretch_k: p.stretch.stiffness,
            stretch_c: p.stretch.damping,
            bend_k: p.bend.stiffness,
            bend_c: p.bend.damping,
            r_min: p.water.r_min,
            r_max: p.water.r_max,
            adhesion: p.water.adhesion,
            wet_gain: (p.water.wetting_rate * h).min(1.0),
            particle_inv_mass: 1.0 / p.water.particle_mass,
            water_drag: p.water.drag,
            capacity: p.water.capacity,
            stride: a.stride() as u32,
            pos_off: off(VertexAttributes::POSITION),
            tan_off: off(VertexAttributes::TANGENT),
            wet_off: off(VertexAttributes::WETNESS),
            incoming,
            max_cells: MAX_CELLS as u32,
            domain_r2: self.water_radius * self.water_radius,
            domain_center: c.extend(0.0).to_array(),
        };
        self.dev
            .queue
            .write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&rec));
    }

    /// Uploads each substep's head transform and placed colliders (from `self.heads`, through
    /// `self.sub_bytes`: no allocation per step).
    fn write_substeps(&mut self) {
        let nc = self.params.colliders.len();
        let bytes = &mut self.sub_bytes;
        for (s, head) in self.heads.iter().enumerate() {
            let at = s * self.sub_stride as usize;
            let m = glam::Mat4::from(*head).to_cols_array();
            bytes[at..at + 64].copy_from_slice(bytemuck::cast_slice(&m));
            for (c, shape) in self.params.colliders.iter().enumerate() {
                let pl: Placed = shape.place(head);
                let rec = ColliderGpu {
                    a: pl.a.extend(pl.radius).to_array(),
                    ab: pl.ab.extend(pl.inv_len2).to_array(),
                };
                let o = at + 64 + 32 * c;
                bytes[o..o + 32].copy_from_slice(bytemuck::bytes_of(&rec));
            }
            debug_assert!(64 + 32 * nc <= self.sub_stride as usize);
        }
        self.dev.queue.write_buffer(&self.sub_buf, 0, bytes);
    }

    /// Advances by `dt` in the configured substeps while the head moves `from` → `to`.
    /// Returns once the work is submitted; failures inside the step show at the next read.
    pub fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<()> {
        self.dev.check()?;
        let h = dt / self.n_sub as f32;
        crate::physics::head::substep_heads_into(from, to, &mut self.heads);
        self.write_substeps();
        let incoming = self.water.as_ref().map_or(0, |w| w.pending);
        self.write_params(h, incoming, to);
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        // The step's speed maximum starts again; failure flags stay until reset.
        enc.clear_buffer(&self.status, 0, Some(4));
        let wet = self.wet();
        {
            let desc = wgpu::ComputePassDescriptor {
                label: Some("step"),
                timestamp_writes: self.timing.as_ref().map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.queries,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
            };
            let mut pass = enc.begin_compute_pass(&desc);
            if let Some(w) = self.water.as_mut().filter(|w| w.pending > 0) {
                pass.set_pipeline(&w.pipes[0]);
                pass.set_bind_group(0, &w.build_bg[w.cur], &[]);
                let (gx, gy) = groups(w.pending);
                pass.dispatch_workgroups(gx, gy, 1);
                w.bound = (w.bound + w.pending).min(self.params.water.capacity);
                w.pending = 0;
            }
            for s in 0..self.n_sub {
                let off = [(s as u64 * self.sub_stride) as u32];
                if let (true, Some(w)) = (wet, self.water.as_mut()) {
                    // Pass water_grid.
                    w.encode_grid(&mut pass, true);
                    let (gx, gy) = groups(w.bound);
                    // Forces, adhesion, integrate, collide; then the particles move.
                    let k = &w.wet_hair;
                    k.encode(
                        &mut pass,
                        &self.hair_bg[self.cur],
                        &off,
                        Some(&w.hair_bg[w.cur]),
                        self.strands_bg.as_ref(),
                        self.points,
                        self.strands,
                    );
                    if let Some(p) = &k.water {
                        pass.set_pipeline(p);
                        pass.set_bind_group(1, &w.hair_bg[w.cur], &[]);
                        pass.dispatch_workgroups(gx, gy, 1);
                    }
                    w.cur = 1 - w.cur;
                } else {
                    self.dry_hair.encode(
                        &mut pass,
                        &self.hair_bg[self.cur],
                        &off,
                        None,
                        self.strands_bg.as_ref(),
                        self.points,
                        self.strands,
                    );
                }
                self.cur = 1 - self.cur;
            }
            if let (true, Some(w)) = (wet, self.water.as_mut()) {
                // Pass water_cull.
                let (gx, gy) = groups(w.bound);
                pass.set_bind_group(0, &w.build_bg[w.cur], &[]);
                pass.set_pipeline(&w.pipes[8]);
                pass.dispatch_workgroups(gx, gy, 1);
                pass.set_pipeline(&w.pipes[9]);
                pass.dispatch_workgroups(1, 1, 1);
                w.cur = 1 - w.cur;
            }
        }
        if let Some(t) = &self.timing {
            enc.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
        }
        self.frame += 1;
        self.vertices_current = false;
        let deferred = self.params.readback == Readback::PreviousFrame && !self.staging.is_empty();
        if self.shares_vertices() {
            // The host may still be drawing the last frame: only the vertex write waits for its
            // release, so the step's passes go in a submission of their own and run meanwhile.
            self.submit(enc);
            enc = self.dev.device.create_command_encoder(&Default::default());
        }
        if deferred || self.shares_vertices() {
            self.encode_vertices(&mut enc);
        }
        let ring_slot = if self.shares_vertices() {
            self.status_slot(&mut enc)
        } else {
            None
        };
        if deferred {
            let k = (self.frame % 2) as usize;
            self.settle(k);
            self.encode_copy(&mut enc, k);
        }
        self.submit(enc);
        if deferred {
            self.map(((self.frame % 2) as usize, self.frame));
        }
        if let Some(k) = ring_slot {
            let s = &mut self.status_ring[k];
            s.frame = Some(self.frame);
            let ready = s.ready.clone();
            s.buf.map_async(wgpu::MapMode::Read, .., move |r| {
                if r.is_ok() {
                    ready.store(true, Ordering::Release);
                }
            });
        }
        self.dev.check()
    }

    fn encode_vertices(&mut self, enc: &mut wgpu::CommandEncoder) {
        if self.vertices_current {
            return;
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.output);
        pass.set_bind_group(0, &self.output_bg[self.cur], &[]);
        let (gx, gy) = groups(self.points);
        pass.dispatch_workgroups(gx, gy, 1);
        drop(pass);
        self.encode_water_vertices(enc);
        self.vertices_current = true;
        self.wrote_vertices = true;
    }

    /// Pass write_water_vertices, where the host draws the particles and they exist.
    fn encode_water_vertices(&mut self, enc: &mut wgpu::CommandEncoder) {
        let (Some(ws), Some(w)) = (&mut self.water_share, &self.water) else {
            return;
        };
        let d = &self.dev.device;
        let bg = ws.bg.get_or_insert_with(|| {
            let mk = |i: usize| {
                pl::bind(
                    d,
                    "water output",
                    &ws.layout,
                    &[&w.particles[i], &w.state, &self.status, &ws.vertices, &ws.draw],
                    None,
                )
            };
            [mk(0), mk(1)]
        });
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&ws.pipe);
        pass.set_bind_group(0, &bg[w.cur], &[]);
        let (gx, gy) = groups(self.params.water.capacity);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// Submits `enc`, telling the device whether it writes the vertices.
    fn submit(&mut self, enc: wgpu::CommandEncoder) {
        let wrote = std::mem::take(&mut self.wrote_vertices);
        self.dev.submit(enc.finish(), wrote);
    }

    /// Whether the host draws straight from the vertex buffer (a host-shared device): then
    /// every step writes it.
    fn shares_vertices(&self) -> bool {
        #[cfg(feature = "vulkan")]
        return self.dev.shared.is_some();
        #[cfg(not(feature = "vulkan"))]
        false
    }

    /// Hands the host the vertex buffer of the last step, with the semaphore values that
    /// order its reads against our next write (see [`crate::gpu::vulkan::SharedSync`]).
    #[cfg(feature = "vulkan")]
    pub fn shared_frame(&mut self) -> Result<crate::gpu::vulkan::SharedFrame> {
        use crate::gpu::vulkan::{raw_buffer, raw_semaphore, SharedFrame};
        self.dev.check()?;
        if self.dev.shared.is_none() {
            return Err(Error::Unsupported(
                "the vertex VkBuffer is shared only by simulations created on the host's VkDevice".into(),
            ));
        }
        if !self.vertices_current {
            let mut enc = self.dev.device.create_command_encoder(&Default::default());
            self.vertices_current = false;
            self.encode_vertices(&mut enc);
            self.submit(enc);
        }
        // A failed step seen by the status ring is reported here, not handed out.
        self.poll_status_ring();
        self.status_error(&self.last)?;
        let buffer =
            raw_buffer(&self.vertices).ok_or_else(|| Error::Device("the vertex buffer has no Vulkan handle".into()))?;
        let Some(sync) = self.dev.shared.as_ref() else {
            return Err(Error::Unsupported("no shared device".into()));
        };
        let (ready, release) = sync.acquire();
        self.dev.check()?;
        Ok(SharedFrame {
            buffer,
            size: self.vertices.size(),
            ready_semaphore: raw_semaphore(sync.ready),
            ready_value: ready,
            release_semaphore: raw_semaphore(sync.release),
            release_value: release,
        })
    }

    /// Hands the host the particles' positions and indirect-draw arguments as Vulkan buffers,
    /// written with each frame's vertices (the frame's semaphores cover them). The first call
    /// makes them (capacity x 16 bytes + 16) and writes the current particles at once.
    #[cfg(feature = "vulkan")]
    pub fn shared_water(&mut self) -> Result<crate::gpu::vulkan::SharedWater> {
        use crate::gpu::vulkan::{raw_buffer, SharedWater};
        self.dev.check()?;
        if self.dev.shared.is_none() {
            return Err(Error::Unsupported(
                "the water VkBuffers are shared only by simulations created on the host's VkDevice".into(),
            ));
        }
        if self.water_share.is_none() {
            let d = &self.dev.device;
            let cap = self.params.water.capacity as u64;
            let layout = pl::layout(
                d,
                "water output",
                &[Slot::Read, Slot::Read, Slot::Read, Slot::ReadWrite, Slot::ReadWrite],
            );
            let module = pl::module(d, "water output", &pl::water_output_source(self.consts));
            let pipe = pl::pipelines(d, &module, &[&layout], &["write_water_vertices"]).remove(0);
            self.water_share = Some(WaterShare {
                vertices: b::buffer(d, "water_vertices", cap * 16, STORAGE | wgpu::BufferUsages::VERTEX),
                draw: b::buffer(d, "water_draw", 16, STORAGE | wgpu::BufferUsages::INDIRECT),
                layout,
                pipe,
                bg: None,
            });
            // The frame already handed out was written without them: write them now and wait,
            // so that the host's next read of this frame finds them (nobody reads them yet).
            // wgpu zero-fills a buffer lazily, at its first use by wgpu, and the host's own
            // commands are not that: clear the draw arguments here, so that a host drawing
            // before any water exists draws nothing rather than what the memory held.
            let mut enc = self.dev.device.create_command_encoder(&Default::default());
            if let Some(ws) = &self.water_share {
                enc.clear_buffer(&ws.draw, 0, None);
            }
            self.encode_water_vertices(&mut enc);
            self.submit(enc);
            self.dev.wait()?;
        }
        let ws = self.water_share.as_ref().expect("made above");
        let handle = |buf| raw_buffer(buf).ok_or_else(|| Error::Device("a water buffer has no Vulkan handle".into()));
        Ok(SharedWater {
            buffer: handle(&ws.vertices)?,
            capacity: self.params.water.capacity,
            draw_buffer: handle(&ws.draw)?,
        })
    }

    /// Picks a free status-ring slot and records the copy of the status block into it; None
    /// when both still wait for the GPU (this step's status is then skipped, never waited for).
    /// Slots whose readback has landed are decoded first: a failed step shows at the next call.
    fn status_slot(&mut self, enc: &mut wgpu::CommandEncoder) -> Option<usize> {
        if self.status_ring.is_empty() {
            for _ in 0..2 {
                self.status_ring.push(Staging {
                    buf: b::buffer(
                        &self.dev.device,
                        "status readback",
                        STATUS_BYTES,
                        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    ),
                    frame: None,
                    ready: Arc::default(),
                });
            }
        }
        self.poll_status_ring();
        let k = self.status_ring.iter().position(|s| s.frame.is_none())?;
        let dst = &self.status_ring[k].buf;
        enc.copy_buffer_to_buffer(&self.status, 0, dst, 0, Some(16));
        if let Some(w) = &self.water {
            enc.copy_buffer_to_buffer(&w.state, 0, dst, 16, Some(16));
        }
        Some(k)
    }

    /// Decodes the status-ring slots whose readback has landed (without waiting) into
    /// `last`, the newest step first, and frees them.
    fn poll_status_ring(&mut self) {
        let _ = self.dev.device.poll(wgpu::PollType::Poll);
        let mut landed: Vec<usize> = (0..self.status_ring.len())
            .filter(|&k| self.status_ring[k].frame.is_some() && self.status_ring[k].ready.load(Ordering::Acquire))
            .collect();
        landed.sort_by_key(|&k| self.status_ring[k].frame);
        for k in landed {
            let s = &mut self.status_ring[k];
            if let Ok(view) = s.buf.get_mapped_range(..) {
                let (st, _) = decode_status(bytemuck::cast_slice(&view), self.water.is_some());
                // A failure, once seen, stays until reset; otherwise the newest status wins.
                if self.last.failed_point.is_none() && !self.last.water_failed {
                    self.last = st;
                }
            }
            s.buf.unmap();
            s.frame = None;
            s.ready.store(false, Ordering::Release);
        }
    }

    fn ensure_staging(&mut self) {
        if !self.staging.is_empty() {
            return;
        }
        let n = if self.params.readback == Readback::PreviousFrame {
            2
        } else {
            1
        };
        let size = STATUS_BYTES + self.vertices.size();
        for _ in 0..n {
            self.staging.push(Staging {
                buf: b::buffer(
                    &self.dev.device,
                    "readback",
                    size,
                    wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                ),
                frame: None,
                ready: Arc::default(),
            });
        }
    }

    /// Unmaps staging slot `k` if it still holds an older frame.
    fn settle(&mut self, k: usize) {
        let s = &mut self.staging[k];
        if s.frame.take().is_some() {
            while !s.ready.load(Ordering::Acquire) {
                if self.dev.device.poll(wgpu::PollType::wait_indefinitely()).is_err() {
                    break;
                }
            }
            s.buf.unmap();
            s.ready.store(false, Ordering::Release);
        }
    }

    fn encode_copy(&self, enc: &mut wgpu::CommandEncoder, k: usize) {
        let dst = &self.staging[k].buf;
        enc.copy_buffer_to_buffer(&self.status, 0, dst, 0, Some(16));
        if let Some(w) = &self.water {
            enc.copy_buffer_to_buffer(&w.state, 0, dst, 16, Some(16));
        }
        enc.copy_buffer_to_buffer(&self.vertices, 0, dst, STATUS_BYTES, Some(self.vertices.size()));
    }

    fn map(&mut self, (k, frame): (usize, u64)) {
        let s = &mut self.staging[k];
        s.frame = Some(frame);
        let ready = s.ready.clone();
        s.buf.map_async(wgpu::MapMode::Read, .., move |r| {
            // A failed map leaves `ready` false; the wait below then reports the device error.
            if r.is_ok() {
                ready.store(true, Ordering::Release);
            }
        });
    }

    /// Waits until slot `k` is mapped; then decodes its status.
    fn wait_mapped(&mut self, k: usize) -> Result<Status> {
        while !self.staging[k].ready.load(Ordering::Acquire) {
            self.dev.wait()?;
            if !self.staging[k].ready.load(Ordering::Acquire) {
                self.dev.check()?;
                return Err(Error::Device("mapping the readback buffer failed".into()));
            }
        }
        let view = self.staging[k]
            .buf
            .get_mapped_range(..STATUS_BYTES)
            .map_err(|e| Error::Device(format!("reading back: {e}")))?;
        let (st, removed) = decode_status(bytemuck::cast_slice(&view), self.water.is_some());
        drop(view);
        if let Some(wt) = &mut self.water {
            wt.bound = st.particles;
            wt.removed = removed;
        }
        self.last = st;
        Ok(st)
    }

    fn status_error(&self, st: &Status) -> Result<()> {
        if let Some(p) = st.failed_point {
            let strand = self.strand_first.partition_point(|&f| f <= p).saturating_sub(1) as u32;
            return Err(Error::Unstable {
                strand,
                detail: "a GPU step produced a non-finite position or velocity".into(),
            });
        }
        if st.water_failed {
            return Err(Error::Unstable {
                strand: u32::MAX,
                detail: "a water particle became non-finite".into(),
            });
        }
        Ok(())
    }

    /// Copies the vertices into `dst` (`points * stride` floats). `Readback::Latest` waits for
    /// the current step; `PreviousFrame` returns the step before it without waiting (the first
    /// read waits). Returns the step number the vertices belong to. Writes nothing on error.
    pub fn read_vertices(&mut self, dst: &mut [f32]) -> Result<u64> {
        self.dev.check()?;
        self.ensure_staging();
        let prev = self.frame.saturating_sub(1);
        let slot = match self.params.readback {
            Readback::PreviousFrame => {
                let find = |f: u64| self.staging.iter().position(|s| s.frame == Some(f));
                find(prev).filter(|_| self.frame > 0).or_else(|| find(self.frame))
            }
            Readback::Latest => None,
        };
        let k = match slot {
            Some(k) => k,
            None => {
                let k = (self.frame % self.staging.len() as u64) as usize;
                self.settle(k);
                let mut enc = self.dev.device.create_command_encoder(&Default::default());
                self.encode_vertices(&mut enc);
                self.encode_copy(&mut enc, k);
                self.submit(enc);
                self.map((k, self.frame));
                k
            }
        };
        let st = self.wait_mapped(k)?;
        self.status_error(&st)?;
        let frame = self.staging[k].frame.unwrap_or(self.frame);
        {
            let view = self.staging[k]
                .buf
                .get_mapped_range(STATUS_BYTES..STATUS_BYTES + dst.len() as u64 * 4)
                .map_err(|e| Error::Device(format!("reading back: {e}")))?;
            dst.copy_from_slice(bytemuck::cast_slice(&view));
        }
        // The slot stays mapped with its frame: a second read of the same frame finds it, and
        // `settle` unmaps it before it is written again.
        Ok(frame)
    }

    /// Reads the status of the last submitted step (waits for it) and remembers it.
    pub fn read_status(&mut self) -> Result<Status> {
        let (st, removed) = self.peek_status()?;
        if let Some(wt) = &mut self.water {
            wt.bound = st.particles;
            wt.removed = removed;
        }
        self.last = st;
        Ok(st)
    }

    /// Reads the status of the last submitted step (waits for it) and the particles removed.
    pub fn peek_status(&self) -> Result<(Status, u64)> {
        let bytes = self.read_buffers(&[(&self.status, 16)], self.water.as_ref().map(|w| &w.state))?;
        Ok(decode_status(bytemuck::cast_slice(&bytes[..32]), self.water.is_some()))
    }

    /// The error a status stands for (a non-finite point or particle), if any.
    pub fn check_status(&self, st: &Status) -> Result<()> {
        self.status_error(st)
    }

    /// The last status read.
    pub fn last_status(&self) -> Status {
        self.last
    }

    /// Particles removed since create or reset (as of the last status read).
    pub fn removed(&self) -> u64 {
        self.water.as_ref().map_or(0, |w| w.removed)
    }

    /// Blocking copy of whole buffers (`(buffer, bytes)`) plus an optional 16-byte tail.
    fn read_buffers(&self, parts: &[(&wgpu::Buffer, u64)], tail: Option<&wgpu::Buffer>) -> Result<Vec<u8>> {
        self.dev.check()?;
        let total: u64 = parts.iter().map(|p| p.1).sum::<u64>() + 16;
        let tmp = b::buffer(
            &self.dev.device,
            "read",
            total,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for (buf, n) in parts {
            if *n > 0 {
                enc.copy_buffer_to_buffer(buf, 0, &tmp, at, Some(*n));
            }
            at += n;
        }
        if let Some(t) = tail {
            enc.copy_buffer_to_buffer(t, 0, &tmp, at, Some(16));
        }
        self.dev.submit(enc.finish(), false);
        let ok = Arc::new(AtomicBool::new(false));
        let flag = ok.clone();
        tmp.map_async(wgpu::MapMode::Read, .., move |r| {
            flag.store(r.is_ok(), Ordering::Release)
        });
        self.dev.wait()?;
        if !ok.load(Ordering::Acquire) {
            return Err(Error::Device("mapping a readback buffer failed".into()));
        }
        let view = tmp
            .get_mapped_range(..)
            .map_err(|e| Error::Device(format!("reading back: {e}")))?;
        Ok(view.to_vec())
    }

    /// Positions, velocities and wetness of every point (blocking; tests and diagnostics).
    pub fn read_state(&self) -> Result<Vec<StateGpu>> {
        let bytes = self.read_buffers(&[(&self.state[self.cur], self.points as u64 * 32)], None)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes[..self.points as usize * 32]))
    }

    /// Every particle (blocking; order is the GPU's).
    pub fn read_water(&self) -> Result<Vec<StateGpu>> {
        let (st, _) = self.peek_status()?;
        let Some(w) = &self.water else { return Ok(Vec::new()) };
        let n = st.particles as u64;
        let bytes = self.read_buffers(&[(&w.particles[w.cur], n * 32)], None)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes[..n as usize * 32]))
    }

    /// Per-cell particle counts of a grid built now over the held particles, with its dims
    /// (tests compare them with the CPU grid's).
    pub fn read_grid_counts(&mut self) -> Result<(glam::IVec3, Vec<u32>)> {
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
        let dims = glam::IVec3::new(g[5] as i32, g[6] as i32, g[7] as i32);
        let cells = g[8] as usize;
        let counts = (0..cells).map(|c| g[16 + c + 1] - g[16 + c]).collect();
        // Without the scatter the counts stay: clear them for the next build.
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        enc.clear_buffer(&w.grid_count, 0, None);
        self.dev.submit(enc.finish(), false);
        self.dev.wait()?;
        Ok((dims, counts))
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

/// Decodes the status block (hair status, then water state when `wet`): the status and the
/// particles removed since reset.
fn decode_status(w: &[u32], wet: bool) -> (Status, u64) {
    let st = Status {
        max_speed: f32::from_bits(w[0]).sqrt(),
        failed_point: (w[1] & 1 != 0).then_some(w[2]),
        water_failed: w[1] & 2 != 0,
        particles: if wet { w[4] } else { 0 },
    };
    (st, if wet { w[6] as u64 } else { 0 })
}

impl Drop for GpuBackend {
    fn drop(&mut self) {
        // Let submitted work finish before buffers go (wgpu keeps them alive, but a host that
        // destroys and recreates expects the device idle).
        let _ = self.dev.device.poll(wgpu::PollType::wait_indefinitely());
    }
}
