//! Held water on the GPU (docs/WET_MODEL.md §1, §3, §4, §7; `shaders/held.wgsl`): each point's
//! water in quanta, its capacity and dry mass, the point records the hair kernels read while
//! water is held (`points_wet`: pass `wet_params` rewrites each step the records the water
//! changes or has left), the ledger block, and the kernels' encoding. Exists only when the
//! scene has held water on.

use super::super::buffers::{self as b, groups, held_ledger as hl, PointGpu, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use super::stamps::{close, PassStamps};
use super::GpuBackend;
use crate::engine::WaterLedger;
use crate::error::{Error, Result};
use crate::params::HeldWater;
use crate::physics::wet;
use crate::timers::Stage;

/// The held-water kernels, by entry point (group 0 only).
pub(super) const HELD_ENTRIES: [&str; 4] = ["wet_params", "soak", "dry", "saturation_out"];
/// Pass flow's kernels (groups 0 and 2: each point's sends, then each point's take).
pub(super) const FLOW_ENTRIES: [&str; 2] = ["flow_send", "flow_take"];
/// Pass drip's kernels (groups 0 and 2: they append particles).
pub(super) const DRIP_ENTRIES: [&str; 3] = ["drip_count", "drip_scan", "drip_emit"];
/// Pass absorb's kernels (groups 0 and 3), per substep.
pub(super) const ABSORB_ENTRIES: [&str; 2] = ["absorb", "absorb_finish"];
const WET_PARAMS: usize = 0;
const SOAK: usize = 1;
const DRY: usize = 2;
const SATURATION: usize = 3;

/// Held water's buffers and pipelines. The bind groups keep every kernel within eight
/// storage buffers (wgpu's default per stage): 0, what all read (over state A or B); 1,
/// soak, dry and saturation_out's own, and wet_params' own beside it; 2, flow and drip's (over
/// particle buffer A or B).
#[derive(Debug)]
pub(super) struct HeldGpu {
    /// The point records with each point's water (what the hair kernels bind).
    pub(super) points_wet: wgpu::Buffer,
    /// Water per point, quanta.
    water: wgpu::Buffer,
    /// Capacity per point, then hold limit per point, quanta (`held.wgsl` `hold_limit`).
    capacity_buf: wgpu::Buffer,
    /// The hold limits (soaking's targets are multiples of them).
    hold: Vec<u32>,
    /// Each point's dry mass, kg, then (with guides only) the water a quantum adds to each
    /// strand of it, kg (`wet::quantum_per_strand` of its bundle; `held.wgsl` `quantum_at`).
    dry_mass: wgpu::Buffer,
    /// The dry masses (what [`HeldGpu::set_bundles`] reads).
    mass: Vec<f32>,
    /// A guide groom's (`consts.bundle_points`): the dry masses' buffer holds each point's
    /// quantum after the masses.
    bundles: bool,
    /// The ledger block (`buffers::held_ledger`).
    ledger: wgpu::Buffer,
    /// Soaking's per-point targets, quanta.
    soak_target: wgpu::Buffer,
    /// The velocities at the step's start (drip only; its size only with flow).
    v0: Option<wgpu::Buffer>,
    /// Per point 1 where `points_wet` holds a record the water changed (wet_params' skip).
    wet_record: wgpu::Buffer,
    /// wet_params' velocity binding where there is no `v0`: one element, never written.
    v_start_placeholder: Option<wgpu::Buffer>,
    /// Flow's two sends a point, then drip's per-point drops and per-workgroup offsets (drip
    /// only; [`drip_scratch_words`]).
    drip_scratch: Option<wgpu::Buffer>,
    /// Groups 0 to 3, then wet_params' group 1.
    layouts: [wgpu::BindGroupLayout; 5],
    /// Group 0 over state A and state B; group 1; group 2 over particle buffer A and B.
    bg0: Option<[wgpu::BindGroup; 2]>,
    bg1: Option<wgpu::BindGroup>,
    /// wet_params' group 1 (`layouts[4]`).
    bg1_params: Option<wgpu::BindGroup>,
    bg2: Option<[wgpu::BindGroup; 2]>,
    /// Group 3 by [sorted particle buffer][output state buffer] (absorption only).
    bg3: Option<[[wgpu::BindGroup; 2]; 2]>,
    absorb_pipes: Vec<wgpu::ComputePipeline>,
    pipes: Vec<wgpu::ComputePipeline>,
    /// Flow's kernels (when water flows) and drip's (when it drips).
    flow_pipes: Vec<wgpu::ComputePipeline>,
    drip_pipes: Vec<wgpu::ComputePipeline>,
    cfg: HeldWater,
}

impl HeldGpu {
    /// Buffers for `pts` (the dry point records) with dry masses `mass`, every point dry;
    /// in a guide groom (`consts.bundle_points`) each point may stand for more than its own
    /// strand ([`HeldGpu::set_bundles`]).
    pub(super) fn new(
        d: &wgpu::Device,
        q: &wgpu::Queue,
        consts: SceneConsts,
        pts: &[PointGpu],
        mass: &[f32],
        cfg: HeldWater,
    ) -> HeldGpu {
        let bundles = consts.bundle_points > 0;
        let n = pts.len() as u64;
        let points_wet = b::buffer(d, "points_wet", std::mem::size_of_val(pts) as u64, STORAGE);
        q.write_buffer(&points_wet, 0, bytemuck::cast_slice(pts));
        // Every strand for itself until the simulation gives the bundles.
        let (mut limits, quantum) = point_limits(mass, &[], &cfg);
        let capacity_buf = b::buffer(d, "held_limits", 2 * n * 4, STORAGE);
        q.write_buffer(&capacity_buf, 0, bytemuck::cast_slice(&limits));
        let hold = limits.split_off(n as usize);
        let dry_mass = b::buffer(d, "held_dry_mass", if bundles { 2 * n * 4 } else { n * 4 }, STORAGE);
        q.write_buffer(&dry_mass, 0, bytemuck::cast_slice(mass));
        if bundles {
            q.write_buffer(&dry_mass, n * 4, bytemuck::cast_slice(&quantum));
        }
        use Slot::*;
        let layouts = [
            pl::layout(d, "held", &[Uniform, Read, ReadWrite, Read, ReadWrite]),
            pl::layout(d, "held own", &[ReadWrite, Read, ReadWrite, Read]),
            pl::layout(d, "held flow drip", &[ReadWrite, ReadWrite, ReadWrite, ReadWrite]),
            pl::layout(d, "held absorb", &[ReadWrite, Read, ReadWrite, ReadWrite]),
            pl::layout_at(
                d,
                "held params",
                &[(0, ReadWrite), (1, Read), (4, ReadWrite), (5, ReadWrite)],
            ),
        ];
        let module = pl::module(d, "held", &pl::held_source(consts, n as u32));
        let params = [Some(&layouts[0]), Some(&layouts[4])];
        let mut pipes = pl::pipelines_sparse(d, &module, &params, &HELD_ENTRIES[..1]);
        let own = [Some(&layouts[0]), Some(&layouts[1])];
        pipes.extend(pl::pipelines_sparse(d, &module, &own, &HELD_ENTRIES[1..]));
        let moving = [Some(&layouts[0]), None, Some(&layouts[2])];
        let flow_pipes = if cfg.flows() {
            pl::pipelines_sparse(d, &module, &moving, &FLOW_ENTRIES)
        } else {
            Vec::new()
        };
        let drip_pipes = if cfg.drips() {
            pl::pipelines_sparse(d, &module, &moving, &DRIP_ENTRIES)
        } else {
            Vec::new()
        };
        let absorbing = [Some(&layouts[0]), None, None, Some(&layouts[3])];
        let absorb_pipes = if cfg.absorbs() {
            pl::pipelines_sparse(d, &module, &absorbing, &ABSORB_ENTRIES)
        } else {
            Vec::new()
        };
        HeldGpu {
            points_wet,
            water: b::buffer(d, "held_water", n * 4, STORAGE),
            capacity_buf,
            hold,
            dry_mass,
            mass: mass.to_vec(),
            bundles,
            ledger: b::buffer(d, "held_ledger", hl::WORDS as u64 * 4, STORAGE),
            soak_target: b::buffer(d, "held_soak_target", n * 4, STORAGE),
            // Without flow, drip reads no step-start velocity: a placeholder of one (a binding
            // must hold at least one element of the array it declares).
            v0: cfg
                .drips()
                .then(|| b::buffer(d, "held_v0", if cfg.flows() { n * 16 } else { 16 }, STORAGE)),
            // Zeroed at creation: every record starts dry.
            wet_record: b::buffer(d, "held_wet_record", n * 4, STORAGE),
            v_start_placeholder: (!cfg.drips()).then(|| b::buffer(d, "held_v_start", 16, STORAGE)),
            drip_scratch: cfg
                .drips()
                .then(|| b::buffer(d, "held_drip", drip_scratch_words(n as u32, cfg.flows()) * 4, STORAGE)),
            layouts,
            bg0: None,
            bg1: None,
            bg1_params: None,
            bg2: None,
            bg3: None,
            absorb_pipes,
            pipes,
            flow_pipes,
            drip_pipes,
            cfg,
        }
    }

    /// Makes groups 0 and 1 over the step parameters, the dry point records and the two
    /// state buffers.
    pub(super) fn bind(
        &mut self,
        d: &wgpu::Device,
        params: &wgpu::Buffer,
        points: &wgpu::Buffer,
        state: &[wgpu::Buffer; 2],
    ) {
        let mk = |i: usize| {
            pl::bind(
                d,
                "held",
                &self.layouts[0],
                &[params, points, &self.water, &self.capacity_buf, &state[i]],
                None,
            )
        };
        self.bg0 = Some([mk(0), mk(1)]);
        self.bg1 = Some(pl::bind(
            d,
            "held own",
            &self.layouts[1],
            &[&self.points_wet, &self.dry_mass, &self.ledger, &self.soak_target],
            None,
        ));
        let v_start = self
            .v0
            .as_ref()
            .or(self.v_start_placeholder.as_ref())
            .expect("one of the two");
        self.bg1_params = Some(pl::bind_at(
            d,
            "held params",
            &self.layouts[4],
            vec![
                (0, self.points_wet.as_entire_binding()),
                (1, self.dry_mass.as_entire_binding()),
                (4, self.wet_record.as_entire_binding()),
                (5, v_start.as_entire_binding()),
            ],
        ));
    }

    /// Makes group 2 (flow and drip) over the particle buffers and the water state block;
    /// without drip, nothing (flow always comes with drip: `HeldWater::drips`).
    pub(super) fn bind_drip(&mut self, d: &wgpu::Device, particles: &[wgpu::Buffer; 2], water_state: &wgpu::Buffer) {
        let (Some(v0), Some(scratch)) = (&self.v0, &self.drip_scratch) else {
            return;
        };
        let mk = |i: usize| {
            pl::bind(
                d,
                "held flow drip",
                &self.layouts[2],
                &[v0, scratch, &particles[i], water_state],
                None,
            )
        };
        self.bg2 = Some([mk(0), mk(1)]);
    }

    /// Makes group 3 (absorption) over the particle buffers, the grid, absorption's scratch
    /// and the state buffers; without absorption, nothing.
    pub(super) fn bind_absorb(
        &mut self,
        d: &wgpu::Device,
        particles: &[wgpu::Buffer; 2],
        grid: &wgpu::Buffer,
        scratch: &wgpu::Buffer,
        state: &[wgpu::Buffer; 2],
    ) {
        if !self.cfg.absorbs() {
            return;
        }
        let mk = |p: usize, o: usize| {
            pl::bind(
                d,
                "held absorb",
                &self.layouts[3],
                &[&particles[p], grid, scratch, &state[o]],
                None,
            )
        };
        self.bg3 = Some([[mk(0, 0), mk(0, 1)], [mk(1, 0), mk(1, 1)]]);
    }

    /// Pass absorb, after a substep's hair kernel: `cur` the substep's input state, `sorted`
    /// the particle buffer in grid order; `particles` bounds the particles held.
    pub(super) fn encode_absorb(
        &self,
        pass: &mut wgpu::ComputePass,
        cur: usize,
        sorted: usize,
        points: u32,
        particles: u32,
    ) {
        let Some(bg3) = &self.bg3 else { return };
        pass.set_bind_group(0, &self.bg0.as_ref().expect("bound at create")[cur], &[]);
        pass.set_bind_group(3, &bg3[sorted][1 - cur], &[]);
        pass.set_pipeline(&self.absorb_pipes[0]);
        let (gx, gy) = groups(points);
        pass.dispatch_workgroups(gx, gy, 1);
        pass.set_pipeline(&self.absorb_pipes[1]);
        let (gx, gy) = groups(particles.max(1));
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// The entry points pass absorb dispatches each substep (none without absorption).
    pub(super) fn absorb_dispatches(&self) -> &'static [&'static str] {
        if self.cfg.absorbs() {
            &ABSORB_ENTRIES
        } else {
            &[]
        }
    }

    /// What the liquid bridges read: each point's water and capacity.
    pub(super) fn bridge_inputs(&self) -> super::bridges::HeldBuffers<'_> {
        super::bridges::HeldBuffers {
            water: &self.water,
            capacity: &self.capacity_buf,
        }
    }

    /// Whether a step may add particles (drops).
    pub(super) fn drips(&self) -> bool {
        self.cfg.drips()
    }

    /// Dispatches one of [`HELD_ENTRIES`] over every point.
    fn dispatch(&self, pass: &mut wgpu::ComputePass, entry: usize, cur: usize, points: u32) {
        pass.set_pipeline(&self.pipes[entry]);
        pass.set_bind_group(0, &self.bg0.as_ref().expect("bound at create")[cur], &[]);
        pass.set_bind_group(1, self.bg1.as_ref().expect("bound at create"), &[]);
        let (gx, gy) = groups(points);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// Pass wet_params, before the substeps (the step's start is state `cur`).
    pub(super) fn encode_before(&self, pass: &mut wgpu::ComputePass, cur: usize, points: u32) {
        pass.set_pipeline(&self.pipes[WET_PARAMS]);
        pass.set_bind_group(0, &self.bg0.as_ref().expect("bound at create")[cur], &[]);
        pass.set_bind_group(1, self.bg1_params.as_ref().expect("bound at create"), &[]);
        let (gx, gy) = groups(points);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// The once-per-step passes after the substeps, in the plan's order (flow, drip, dry),
    /// then the saturation the vertices show when the water can have changed. `cur` is the
    /// state buffer that holds the step's result, `particles` the particle buffer that holds
    /// the particles. `stamps` closes the stages `flow`, `drip` and `dry` when stage timing is
    /// on.
    pub(super) fn encode_after(
        &self,
        pass: &mut wgpu::ComputePass,
        cur: usize,
        particles: usize,
        points: u32,
        stamps: &mut Option<PassStamps>,
    ) {
        let (gx, gy) = groups(points);
        if let Some(bg2) = &self.bg2 {
            pass.set_bind_group(0, &self.bg0.as_ref().expect("bound at create")[cur], &[]);
            pass.set_bind_group(2, &bg2[particles], &[]);
            for p in &self.flow_pipes {
                pass.set_pipeline(p);
                pass.dispatch_workgroups(gx, gy, 1);
            }
            if !self.flow_pipes.is_empty() {
                close(stamps, pass, Stage::Flow);
            }
            let (dx, dy) = drip_groups(points);
            for (k, p) in self.drip_pipes.iter().enumerate() {
                pass.set_pipeline(p);
                if k == 1 {
                    pass.dispatch_workgroups(1, 1, 1); // drip_scan: one workgroup
                } else {
                    pass.dispatch_workgroups(dx, dy, 1);
                }
            }
            if !self.drip_pipes.is_empty() {
                close(stamps, pass, Stage::Drip);
            }
        }
        // dry writes the saturation as it goes; without it, saturation_out does.
        if self.cfg.dries() {
            self.dispatch(pass, DRY, cur, points);
        } else if self.changes() {
            self.dispatch(pass, SATURATION, cur, points);
        }
        if self.changes() {
            close(stamps, pass, Stage::Dry);
        }
    }

    /// Whether the step's passes can change the water (so the saturation is written again).
    fn changes(&self) -> bool {
        self.cfg.dries() || self.cfg.flows() || self.cfg.drips() || self.cfg.absorbs()
    }

    /// The entry points a step dispatches before its substeps and after them.
    pub(super) fn dispatches(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let mut after = Vec::new();
        if self.cfg.flows() {
            after.extend_from_slice(&FLOW_ENTRIES);
        }
        if self.cfg.drips() {
            after.extend_from_slice(&DRIP_ENTRIES);
        }
        if self.cfg.dries() {
            after.push(HELD_ENTRIES[DRY]);
        } else if self.changes() {
            after.push(HELD_ENTRIES[SATURATION]);
        }
        (vec![HELD_ENTRIES[WET_PARAMS]], after)
    }

    /// Wets every point up to `s` times its hold limit (never down), booked as added; the
    /// targets are the CPU's (`wet::soak_target`), so both backends soak alike.
    pub(super) fn soak(
        &self,
        dev: &wgpu::Device,
        q: &wgpu::Queue,
        s: f32,
        cur: usize,
        points: u32,
    ) -> wgpu::CommandBuffer {
        let target: Vec<u32> = self.hold.iter().map(|&c| wet::soak_target(c, s)).collect();
        q.write_buffer(&self.soak_target, 0, bytemuck::cast_slice(&target));
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.dispatch(&mut pass, SOAK, cur, points);
        }
        enc.finish()
    }

    /// [`crate::cpu::held::Held::set_bundles`]: each point's capacity and hold limit are its
    /// bundle's (`bundle` per point, in the groom's order; empty: 1), and a quantum adds
    /// `1 / bundle` of its mass to the strand; `water`, where given, replaces each point's.
    /// Only a guide groom's simulation (made with `bundles`) is given bundles.
    pub(super) fn set_bundles(&mut self, q: &wgpu::Queue, bundle: &[f32], water: Option<&[u32]>) {
        let n = self.mass.len();
        let (mut limits, quantum) = point_limits(&self.mass, bundle, &self.cfg);
        q.write_buffer(&self.capacity_buf, 0, bytemuck::cast_slice(&limits));
        // Only a guide groom's buffers hold the quanta (`HeldGpu::new`).
        if self.bundles {
            q.write_buffer(&self.dry_mass, n as u64 * 4, bytemuck::cast_slice(&quantum));
        }
        self.hold = limits.split_off(n);
        if let Some(w) = water {
            q.write_buffer(&self.water, 0, bytemuck::cast_slice(w));
        }
    }

    /// The buffer of each point's water, quanta.
    pub(super) fn water_buffer(&self) -> &wgpu::Buffer {
        &self.water
    }

    /// Dry again, with an empty ledger.
    pub(super) fn reset(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.water, 0, None);
        enc.clear_buffer(&self.ledger, 0, None);
    }

    /// The buffers to read for [`HeldGpu::ledger_from`]: the water, then the ledger block.
    pub(super) fn ledger_parts(&self, points: u32) -> [(&wgpu::Buffer, u64); 2] {
        [(&self.water, points as u64 * 4), (&self.ledger, hl::WORDS as u64 * 4)]
    }

    /// The hair's side of the ledger from the bytes of [`HeldGpu::ledger_parts`].
    pub(super) fn ledger_from(bytes: &[u8], points: u32) -> WaterLedger {
        let words: &[u32] = bytemuck::cast_slice(&bytes[..(points as usize + hl::WORDS as usize) * 4]);
        let (water, block) = words.split_at(points as usize);
        let count = |at: u32| block[at as usize] as u64 | (block[at as usize + 1] as u64) << 32;
        WaterLedger {
            added: count(hl::ADDED),
            held: water.iter().map(|&q| q as u64).sum(),
            evaporated: count(hl::EVAPORATED),
            ..WaterLedger::default()
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        [
            &self.points_wet,
            &self.water,
            &self.capacity_buf,
            &self.dry_mass,
            &self.ledger,
            &self.soak_target,
            &self.wet_record,
        ]
        .into_iter()
        .chain(&self.v0)
        .chain(&self.v_start_placeholder)
        .chain(&self.drip_scratch)
        .map(|b| b.size() as usize)
        .sum()
    }
}

/// Each point's capacity, then each point's hold limit (quanta), and each point's water per
/// quantum and strand (kg), for dry masses `mass`, point `i` standing for `bundle[i]` strands
/// (empty: every one for itself; `wet::bundle_limits`, `wet::quantum_per_strand`).
fn point_limits(mass: &[f32], bundle: &[f32], cfg: &HeldWater) -> (Vec<u32>, Vec<f32>) {
    let n = mass.len();
    let (mut limits, mut quantum) = (vec![0u32; 2 * n], vec![0.0f32; n]);
    for (i, &m) in mass.iter().enumerate() {
        let k = bundle.get(i).copied().unwrap_or(1.0);
        (limits[i], limits[n + i]) = wet::bundle_limits(m, k, cfg.capacity_ratio, cfg.free_ratio);
        quantum[i] = wet::quantum_per_strand(k);
    }
    (limits, quantum)
}

/// Workgroups (x, y) of drip_count and drip_emit over `points`: [`b::DRIP_WG`] points each.
fn drip_groups(points: u32) -> (u32, u32) {
    // `groups` counts workgroups of WG invocations.
    groups(points.div_ceil(b::DRIP_WG / b::WG))
}

/// Words of the flow and drip scratch over `points`: flow's two sends a point (when water
/// flows), or drip's drop a point and its count, then first slot, per workgroup (drip runs
/// after flow and writes over its sends).
fn drip_scratch_words(points: u32, flows: bool) -> u64 {
    let (gx, gy) = drip_groups(points);
    let drip = points as u64 + gx as u64 * gy as u64;
    if flows {
        drip.max(2 * points as u64)
    } else {
        drip
    }
}

impl GpuBackend {
    /// Wets every point up to `s` times its hold limit (held water only).
    pub fn soak(&mut self, s: f32) -> Result<()> {
        self.dev.check()?;
        let h = self.held.as_ref().ok_or_else(|| {
            Error::Unsupported("this simulation holds no water (SimParams::held_water is off)".into())
        })?;
        let cmd = h.soak(&self.dev.device, &self.dev.queue, s, self.cur, self.points);
        self.dev.submit(cmd, false);
        self.vertices_current = false;
        self.dev.check()
    }

    /// Where the water is, in quanta (held water only; one blocking read): the hair's counts,
    /// each particle's water (those waiting to join included), and what left with culled and
    /// cleared particles.
    pub fn ledger(&self) -> Option<Result<WaterLedger>> {
        let h = self.held.as_ref()?;
        Some((|| {
            let hair = h.ledger_parts(self.points);
            let hair_bytes: u64 = hair.iter().map(|p| p.1).sum();
            let mut parts = hair.to_vec();
            // The water's state block and every particle slot that may be live (the host's
            // bound), read with the hair's counts in one copy.
            if let Some(w) = &self.water {
                parts.push((&w.state, w.state.size()));
                parts.push((&w.particles[w.cur], w.bound as u64 * 32));
            }
            let bytes = self.read_buffers(&parts, None)?;
            let mut l = HeldGpu::ledger_from(&bytes, self.points);
            let q = wet::to_quanta(self.params.water.particle_mass as f64) as u64;
            l.added += self.particles_added * q;
            l.left = self.left_cleared;
            if let Some(w) = &self.water {
                let at = hair_bytes as usize;
                let words: &[u32] = bytemuck::cast_slice(&bytes[at..at + w.state.size() as usize]);
                let left = b::water_state::LEFT as usize;
                l.left += words[left] as u64 | (words[left + 1] as u64) << 32;
                let live = words[b::water_state::HELD as usize].min(w.bound) as usize;
                let at = at + w.state.size() as usize;
                let particles: Vec<b::ParticleGpu> = bytemuck::pod_collect_to_vec(&bytes[at..at + live * 32]);
                l.in_particles = particles.iter().map(|p| p.mass as u64).sum::<u64>() + w.pending as u64 * q;
            }
            Ok(l)
        })())
    }

    /// [`crate::engine::Engine::set_bundles`]: each point's bundle, for eq. 2's reaction and
    /// absorption (into the water's absorption scratch, once there is water), and with held
    /// water the limits and quanta.
    pub fn set_bundles(&mut self, bundle: &[f32], water: Option<&[u32]>) -> Result<()> {
        self.dev.check()?;
        // Only a guide groom's simulation has room for them (`consts.bundle_points`).
        if self.consts.bundle_points > 0 {
            self.bundle = vec![1.0; self.points as usize];
            for (s, w) in self.strand_first.windows(2).enumerate() {
                let k = bundle.get(s).copied().unwrap_or(1.0);
                self.bundle[w[0] as usize..w[1] as usize].fill(k);
            }
            if let Some(w) = &self.water {
                self.write_bundles(&w.absorb);
            }
        }
        if let Some(h) = &mut self.held {
            h.set_bundles(&self.dev.queue, &self.bundle, water);
            self.vertices_current = false;
        }
        self.dev.check()
    }

    /// Writes each point's bundle where `absorb.wgsl` `bundle_at` reads it in the water's
    /// absorption scratch `absorb` (`buffers::absorb_words::bundles_at`; a guide groom's only).
    pub(super) fn write_bundles(&self, absorb: &wgpu::Buffer) {
        if self.bundle.is_empty() {
            return;
        }
        let at = b::absorb_words::bundles_at(
            self.params.held_water.absorbs(),
            self.params.water.capacity,
            self.points,
        );
        self.dev
            .queue
            .write_buffer(absorb, at as u64 * 4, bytemuck::cast_slice(&self.bundle));
    }

    /// Each point's held water, quanta (one blocking read; empty without held water).
    pub fn held_water(&self) -> Result<Vec<u32>> {
        let Some(h) = &self.held else {
            return Ok(Vec::new());
        };
        let n = self.points as usize;
        let bytes = self.read_buffers(&[(h.water_buffer(), n as u64 * 4)], None)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes[..n * 4]))
    }

    /// The water in the particles held now, quanta (blocking).
    pub(super) fn particle_water(&self) -> Result<u64> {
        Ok(self.read_water()?.iter().map(|p| p.mass as u64).sum())
    }
}
