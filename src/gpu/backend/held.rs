//! Held water on the GPU (docs/WET_MODEL.md §1, §3, §4, §7; `shaders/held.wgsl`): each point's
//! water in quanta, its capacity and dry mass, the point records the hair kernels read while
//! water is held (`points_wet`, rewritten by pass `wet_params` every step), the ledger block,
//! and the kernels' encoding. Exists only when the scene has held water on.

use super::super::buffers::{self as b, groups, held_ledger as hl, PointGpu, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use super::GpuBackend;
use crate::engine::WaterLedger;
use crate::error::{Error, Result};
use crate::params::HeldWater;
use crate::physics::wet;

/// The held-water kernels, by entry point.
pub(super) const HELD_ENTRIES: [&str; 4] = ["wet_params", "soak", "dry", "saturation_out"];

/// Held water's buffers and pipelines.
#[derive(Debug)]
pub(super) struct HeldGpu {
    /// The point records with each point's water (what the hair kernels bind).
    pub(super) points_wet: wgpu::Buffer,
    /// Water per point, quanta.
    water: wgpu::Buffer,
    /// Capacity per point, quanta (the host keeps a copy for soaking's targets).
    capacity_buf: wgpu::Buffer,
    capacity: Vec<u32>,
    dry_mass: wgpu::Buffer,
    /// The ledger block (`buffers::held_ledger`).
    ledger: wgpu::Buffer,
    /// Soaking's per-point targets, quanta.
    soak_target: wgpu::Buffer,
    /// Bind groups over state A and state B.
    bg: Option<[wgpu::BindGroup; 2]>,
    layout: wgpu::BindGroupLayout,
    pipes: Vec<wgpu::ComputePipeline>,
    cfg: HeldWater,
}

impl HeldGpu {
    /// Buffers for `pts` (the dry point records) with dry masses `mass`, every point dry.
    pub(super) fn new(
        d: &wgpu::Device,
        q: &wgpu::Queue,
        consts: SceneConsts,
        pts: &[PointGpu],
        mass: &[f32],
        cfg: HeldWater,
    ) -> HeldGpu {
        let n = pts.len() as u64;
        let points_wet = b::buffer(d, "points_wet", std::mem::size_of_val(pts) as u64, STORAGE);
        q.write_buffer(&points_wet, 0, bytemuck::cast_slice(pts));
        let capacity: Vec<u32> = mass.iter().map(|&m| wet::capacity(m, cfg.capacity_ratio)).collect();
        let capacity_buf = b::buffer(d, "held_capacity", n * 4, STORAGE);
        q.write_buffer(&capacity_buf, 0, bytemuck::cast_slice(&capacity));
        let dry_mass = b::buffer(d, "held_dry_mass", n * 4, STORAGE);
        q.write_buffer(&dry_mass, 0, bytemuck::cast_slice(mass));
        let layout = pl::layout(
            d,
            "held",
            &[
                Slot::Uniform,
                Slot::Read,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
                Slot::ReadWrite,
                Slot::Read,
            ],
        );
        let module = pl::module(d, "held", &pl::held_source(consts));
        let pipes = pl::pipelines(d, &module, &[&layout], &HELD_ENTRIES);
        HeldGpu {
            points_wet,
            water: b::buffer(d, "held_water", n * 4, STORAGE),
            capacity_buf,
            capacity,
            dry_mass,
            ledger: b::buffer(d, "held_ledger", hl::WORDS as u64 * 4, STORAGE),
            soak_target: b::buffer(d, "held_soak_target", n * 4, STORAGE),
            bg: None,
            layout,
            pipes,
            cfg,
        }
    }

    /// Makes the bind groups over the step parameters, the dry point records and the two
    /// state buffers (once they exist).
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
                &self.layout,
                &[
                    params,
                    points,
                    &self.points_wet,
                    &self.water,
                    &self.capacity_buf,
                    &self.dry_mass,
                    &state[i],
                    &self.ledger,
                    &self.soak_target,
                ],
                None,
            )
        };
        self.bg = Some([mk(0), mk(1)]);
    }

    fn dispatch(&self, pass: &mut wgpu::ComputePass, entry: usize, cur: usize, points: u32) {
        let bg = self.bg.as_ref().expect("bound at create");
        pass.set_pipeline(&self.pipes[entry]);
        pass.set_bind_group(0, &bg[cur], &[]);
        let (gx, gy) = groups(points);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// Pass wet_params, before the substeps.
    pub(super) fn encode_before(&self, pass: &mut wgpu::ComputePass, cur: usize, points: u32) {
        self.dispatch(pass, 0, cur, points);
    }

    /// The once-per-step passes after the substeps (dry), then the saturation the vertices
    /// show when the water can have changed; `cur` is the state buffer that holds the step's
    /// result.
    pub(super) fn encode_after(&self, pass: &mut wgpu::ComputePass, cur: usize, points: u32) {
        if self.cfg.dries() {
            self.dispatch(pass, 2, cur, points);
            self.dispatch(pass, 3, cur, points);
        }
    }

    /// The entry points a step dispatches before its substeps and after them.
    pub(super) fn dispatches(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let after = if self.cfg.dries() {
            vec![HELD_ENTRIES[2], HELD_ENTRIES[3]]
        } else {
            Vec::new()
        };
        (vec![HELD_ENTRIES[0]], after)
    }

    /// Wets every point up to saturation `s` of its capacity (never down), booked as added;
    /// the targets are the CPU's (`floor(capacity s)`), so both backends soak alike.
    pub(super) fn soak(
        &self,
        dev: &wgpu::Device,
        q: &wgpu::Queue,
        s: f32,
        cur: usize,
        points: u32,
    ) -> wgpu::CommandBuffer {
        let target: Vec<u32> = self
            .capacity
            .iter()
            .map(|&c| (c as f64 * s as f64).floor() as u32)
            .collect();
        q.write_buffer(&self.soak_target, 0, bytemuck::cast_slice(&target));
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.dispatch(&mut pass, 1, cur, points);
        }
        enc.finish()
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
        ]
        .iter()
        .map(|b| b.size() as usize)
        .sum()
    }
}

impl GpuBackend {
    /// Wets every point up to saturation `s` of its capacity (held water only).
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

    /// Where the water is, in quanta (held water only; blocking). Particles carry
    /// `particle_mass` each and keep it (the GPU does not absorb yet), so the particles' side
    /// is their counts: in flight now, and the rest of those added as left.
    pub fn ledger(&self) -> Option<Result<WaterLedger>> {
        let h = self.held.as_ref()?;
        Some((|| {
            let (st, _) = self.peek_status()?;
            let bytes = self.read_buffers(&h.ledger_parts(self.points), None)?;
            let mut l = HeldGpu::ledger_from(&bytes, self.points);
            let q = wet::to_quanta(self.params.water.particle_mass as f64) as u64;
            let now = st.particles as u64 + self.water.as_ref().map_or(0, |w| w.pending as u64);
            l.added += self.particles_added * q;
            l.in_particles = now * q;
            l.left = (self.particles_added - now) * q;
            Ok(l)
        })())
    }
}
