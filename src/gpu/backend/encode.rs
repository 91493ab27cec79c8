//! A step's command buffers: the per-step parameters and per-substep heads and colliders,
//! then the passes of every substep in the plan's order, the vertex output, and the
//! submissions (split where the host shares the vertex buffer).

use super::super::buffers::{groups, ColliderGpu, Params, NO_ATTRIBUTE, SUBSTEP_HEAD_BYTES};
use super::super::pipelines as pl;
use super::stamps::close;
use super::GpuBackend;
use crate::error::Result;
use crate::params::{Integrator, Readback, SimParams, VertexAttributes};
use crate::physics::bdf2::Bdf2Blend;
use crate::physics::collide::Placed;
use crate::physics::hash_grid::buckets_for;
use crate::timers::Stage;
use glam::Affine3A;
use std::sync::atomic::Ordering;

/// Bytes of one placed collider in a substep's uniform.
const COLLIDER_BYTES: usize = std::mem::size_of::<ColliderGpu>();

impl GpuBackend {
    pub(super) fn write_params(&self, h: f32, incoming: u32, to: &Affine3A) {
        let p = &self.params;
        let a = p.attributes;
        let off = |bit| a.offset(bit).map_or(NO_ATTRIBUTE, |o| o as u32);
        let c = to.transform_point3(self.domain.center_local);
        let hair_drag = p.hair_drag();
        let limit = crate::physics::pull_limit::PullLimit::new(
            h,
            p.water.r_min,
            p.water.r_max,
            (!p.held_water.absorbs()).then_some(p.water.adhesion),
            self.pull_weight_max,
        );
        let [pile_cell, pile_inv_cell, pile_unit, pile_inv_unit] = pile_scale(p);
        let rec = Params {
            h,
            inv_h: 1.0 / h,
            drag: hair_drag.per_point,
            friction: p.friction,
            g: p.gravity.extend(0.0).to_array(),
            points: self.active_points,
            strands: self.active_strands,
            r_min: p.water.r_min,
            r_max: p.water.r_max,
            adhesion: p.water.adhesion,
            // With held water, wetness is the saturation (written by the held-water passes).
            wet_gain: if p.held_water.enabled {
                0.0
            } else {
                (p.water.wetting_rate * h).min(1.0)
            },
            particle_inv_mass: 1.0 / p.water.particle_mass,
            water_drag_rate: p.water.drag * (1.0 / p.water.particle_mass),
            capacity: p.water.capacity,
            stride: a.stride() as u32,
            pos_off: off(VertexAttributes::POSITION),
            tan_off: off(VertexAttributes::TANGENT),
            wet_off: off(VertexAttributes::WETNESS),
            incoming,
            max_buckets: buckets_for(p.water.capacity as usize) as u32,
            domain_r2: self.domain.radius * self.domain.radius,
            domain_center: c.extend(0.0).to_array(),
            wind: self.wind.extend(0.0).to_array(),
            dt: h * self.n_sub as f32,
            dry_time: p.held_water.dry_time,
            dry_air_speed: p.held_water.dry_air_speed,
            wet_bend_ratio: p.held_water.wet_bend_ratio,
            massive: p.held_water.enabled as u32,
            drag_scale: hair_drag.scale,
            flow_speed: if p.held_water.flows() {
                p.held_water.flow_speed()
            } else {
                0.0
            },
            min_drop: crate::physics::wet::to_quanta(p.held_water.drip_mass as f64).max(1),
            absorbs: p.held_water.absorbs() as u32,
            absorb_take: crate::physics::wet::absorb_take(p.held_water.absorb_rate, h),
            strength_per_quantum: (p.water.adhesion as f64 * crate::physics::wet::WATER_QUANTUM
                / p.water.particle_mass as f64) as f32,
            absorb_last: (crate::physics::wet::to_quanta(p.water.particle_mass as f64) as f64
                * crate::physics::wet::ABSORB_LAST_FRACTION) as u32,
            bridge_length: if p.held_water.bridges() {
                p.held_water.bridge_length_for(&p.water)
            } else {
                0.0
            },
            bridge_tension: p.held_water.bridge_tension,
            bridge_turn: self.bridges.as_ref().map_or(0, |b| b.turn()),
            bridge_masks: if p.held_water.bridges() {
                self.points * crate::gpu::buffers::bridge_words::WORDS
            } else {
                0
            },
            adhesion_scale: p.adhesion_share().scale,
            pull_slope_h2: limit.slope_h2,
            pull_free: limit.free,
            pile_cell,
            pile_inv_cell,
            pile_unit,
            pile_inv_unit,
            pad0: 0,
        };
        self.dev
            .queue
            .write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&rec));
    }

    /// Uploads each substep's head transform and placed colliders (from `self.heads` and the
    /// colliders' own frames, through `self.sub_bytes`: no allocation per step).
    pub(super) fn write_substeps(&mut self, h: f32, from: &Affine3A) {
        let nc = self.params.colliders.len();
        let bytes = &mut self.sub_bytes;
        // BDF2's blends for the first substep and the others, as the CPU picks them.
        let bdf2 = if self.integrator == Integrator::BDF2 {
            self.bdf2.frame(h, self.heads.len() as u32)
        } else {
            (Bdf2Blend::euler(h), Bdf2Blend::euler(h))
        };
        let n_sub = self.heads.len();
        for (s, head) in self.heads.iter().enumerate() {
            let at = s * self.sub_stride as usize;
            let m = glam::Mat4::from(*head).to_cols_array();
            bytes[at..at + 64].copy_from_slice(bytemuck::cast_slice(&m));
            // The implicit solve's start blend and step.
            let blend = if s == 0 { bdf2.0 } else { bdf2.1 };
            let b = [blend.a, blend.b, blend.h, 1.0 / blend.h];
            let head_end = at + SUBSTEP_HEAD_BYTES as usize;
            bytes[at + 64..head_end].copy_from_slice(bytemuck::cast_slice(&b));
            for (c, shape) in self.params.colliders.iter().enumerate() {
                let start = if s == 0 { from } else { &self.heads[s - 1] };
                let pl: Placed = self.collider_frames.place(c, shape, [start, head], s, n_sub, 1.0 / h);
                let rec = ColliderGpu {
                    a: pl.a.extend(pl.radius).to_array(),
                    ab: pl.ab.extend(pl.inv_len2).to_array(),
                    va: pl.va.extend(0.0).to_array(),
                    vab: pl.vab.extend(0.0).to_array(),
                };
                let o = head_end + COLLIDER_BYTES * c;
                bytes[o..o + COLLIDER_BYTES].copy_from_slice(bytemuck::bytes_of(&rec));
            }
            debug_assert!(SUBSTEP_HEAD_BYTES as usize + COLLIDER_BYTES * nc <= self.sub_stride as usize);
        }
        self.dev.queue.write_buffer(&self.sub_buf, 0, bytes);
    }

    /// Advances by `dt` in the configured substeps while the head moves `from` → `to`.
    /// Returns once the work is submitted; failures inside the step show at the next read.
    pub fn step(&mut self, dt: f32, from: &Affine3A, to: &Affine3A) -> Result<()> {
        self.dev.check()?;
        let h = dt / self.n_sub as f32;
        crate::physics::head::substep_heads_into(from, to, &mut self.heads);
        self.write_substeps(h, from);
        if let Some(r) = &mut self.roots {
            r.write_substeps(&self.dev.queue, self.n_sub);
        }
        if let Some(sd) = &mut self.sdf {
            sd.write_substeps(&self.dev.queue, self.n_sub, 1.0 / h);
            if let (Some(w), None) = (&self.water, &sd.water_bg) {
                sd.water_bg = Some(sd.water_groups(&self.dev.device, &self.params_buf, &w.particles, &w.grid));
            }
        }
        let incoming = self.water.as_ref().map_or(0, |w| w.pending);
        self.write_params(h, incoming, to);
        let mut enc = self.dev.device.create_command_encoder(&Default::default());
        // The step's speed maximum starts again; failure flags stay until reset.
        enc.clear_buffer(&self.status, 0, Some(4));
        if let Some(v) = &self.volume {
            v.prepare(&self.dev.queue, &mut enc, from, dt);
        }
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
            let stamps = &mut self.stamps;
            if let Some(s) = stamps {
                s.open(&mut pass);
            }
            if let Some(h) = &self.held {
                h.encode_before(&mut pass, self.cur, self.active_points); // pass wet_params
                close(stamps, &mut pass, Stage::WetParams);
            }
            if let Some(br) = &mut self.bridges {
                br.encode(&mut pass, self.cur, self.active_points); // pass hair_grid
                close(stamps, &mut pass, Stage::HairGrid);
            }
            if let Some(v) = &self.volume {
                v.encode(&mut pass, self.cur); // pass volume
                close(stamps, &mut pass, Stage::Volume);
            }
            let bridges = self.bridges.as_ref().map(|b| &b.cohesion_bg);
            if let Some(w) = self.water.as_mut().filter(|w| w.pending > 0) {
                pass.set_pipeline(&w.pipes[0]);
                pass.set_bind_group(0, &w.build_bg[w.cur], &[]);
                let (gx, gy) = groups(w.pending);
                pass.dispatch_workgroups(gx, gy, 1);
                w.bound = (w.bound + w.pending).min(self.params.water.capacity);
                w.pending = 0;
                // The new particles' insertion, booked with the grid that sorts them.
                close(stamps, &mut pass, Stage::WaterGrid);
            }
            if let (true, Some(w)) = (wet, self.water.as_mut()) {
                if let Some(p) = &w.piles {
                    // Drops that meet coalesce: the substeps see their sources (booked with
                    // the grid, as on the CPU).
                    p.encode_group(&mut pass, &mut w.cur, w.bound);
                    close(stamps, &mut pass, Stage::WaterGrid);
                }
            }
            for s in 0..self.n_sub {
                let off = [(s as u64 * self.sub_stride) as u32];
                if let (true, Some(w)) = (wet, self.water.as_mut()) {
                    // Pass water_grid.
                    w.encode_grid(&mut pass, true);
                    close(stamps, &mut pass, Stage::WaterGrid);
                    let (gx, gy) = groups(w.bound);
                    if let Some(r) = &self.roots {
                        // Pass pin_roots (booked with the hair kernel after it).
                        r.encode_pin(&mut pass, s);
                    }
                    // Forces, adhesion, integrate, collide; then the particles move.
                    let k = &w.wet_hair;
                    k.encode(
                        &mut pass,
                        &self.hair_bg[self.cur],
                        &off,
                        Some(&w.hair_bg[w.cur]),
                        self.strands_bg.as_ref(),
                        bridges,
                        self.active_points,
                        self.active_strands,
                        stamps,
                    );
                    if let Some(sd) = &self.sdf {
                        // Pass collide's SDF part, booked with the hair kernel that holds the
                        // analytic colliders.
                        sd.encode_hair(&mut pass, self.cur, s, self.active_points);
                        pass.set_bind_group(0, &self.hair_bg[self.cur], &off);
                        close(stamps, &mut pass, Stage::Blocks);
                    }
                    if let Some(r) = &w.reactions {
                        // Pass reactions: the particles gather what the hair kernel's pulls
                        // gave them (booked with the hair kernel).
                        r.encode(&mut pass, w.cur, &w.dispatch, self.active_points, w.bound);
                        pass.set_bind_group(0, &self.hair_bg[self.cur], &off);
                        close(stamps, &mut pass, Stage::Blocks);
                    }
                    if let Some(h) = self.held.as_ref().filter(|h| !h.absorb_dispatches().is_empty()) {
                        // Pass absorb: the particles give the hair what it asked for (its own
                        // bind groups; water_integrate's go back after it).
                        h.encode_absorb(&mut pass, self.cur, 1 - w.cur, self.active_points, w.bound);
                        pass.set_bind_group(0, &self.hair_bg[self.cur], &off);
                        close(stamps, &mut pass, Stage::Absorb);
                    }
                    if let Some(p) = &k.water {
                        pass.set_pipeline(p);
                        pass.set_bind_group(1, &w.hair_bg[w.cur], &[]);
                        pass.dispatch_workgroups(gx, gy, 1);
                        if let Some(sd) = &self.sdf {
                            // The particles' SDF push, part of water_integrate as on the CPU.
                            sd.encode_water(&mut pass, w.cur, s, w.bound);
                            pass.set_bind_group(0, &self.hair_bg[self.cur], &off);
                        }
                        close(stamps, &mut pass, Stage::WaterIntegrate);
                    }
                    w.cur = 1 - w.cur;
                } else {
                    if let Some(r) = &self.roots {
                        r.encode_pin(&mut pass, s);
                    }
                    self.dry_hair.encode(
                        &mut pass,
                        &self.hair_bg[self.cur],
                        &off,
                        None,
                        self.strands_bg.as_ref(),
                        bridges,
                        self.active_points,
                        self.active_strands,
                        stamps,
                    );
                    if let Some(sd) = &self.sdf {
                        sd.encode_hair(&mut pass, self.cur, s, self.active_points);
                        close(stamps, &mut pass, Stage::Blocks);
                    }
                }
                self.cur = 1 - self.cur;
            }
            if let Some(h) = &self.held {
                // Passes flow, drip, dry, then the saturation the vertices show.
                let particles = self.water.as_ref().map_or(0, |w| w.cur);
                h.encode_after(&mut pass, self.cur, particles, self.active_points, stamps);
                if let (true, Some(w)) = (h.drips(), self.water.as_mut()) {
                    // Each point sheds at most one drop a step; a status read makes it exact.
                    w.bound = (w.bound + self.active_points).min(self.params.water.capacity);
                }
            }
            if let (true, Some(w)) = (wet, self.water.as_mut()) {
                if let Some(p) = &w.piles {
                    // The drops take their sources' places again.
                    p.encode_spread(&mut pass, &mut w.cur, w.bound);
                }
                // Pass water_cull.
                let (gx, gy) = groups(w.bound);
                pass.set_bind_group(0, &w.build_bg[w.cur], &[]);
                pass.set_pipeline(&w.pipes[8]);
                pass.dispatch_workgroups(gx, gy, 1);
                pass.set_pipeline(&w.pipes[9]);
                pass.dispatch_workgroups(1, 1, 1);
                w.cur = 1 - w.cur;
                close(stamps, &mut pass, Stage::WaterCull);
            }
        }
        if let Some(t) = &self.timing {
            enc.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
        }
        if let Some(s) = &self.stamps {
            s.resolve(&mut enc);
        }
        self.frame += 1;
        self.vertices_current = false;
        let deferred = self.params.readback == Readback::PREVIOUS_FRAME && !self.staging.is_empty();
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
        self.encode_sample(&mut enc);
        self.submit(enc);
        if deferred {
            self.map(((self.frame % 2) as usize, self.frame));
        }
        self.map_sample();
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
        if let Some(s) = &self.stamps {
            // Timing per stage waits for the step (it is a measuring mode).
            let bytes = self.read_buffers(&[s.resolved()], None)?;
            self.stamps.as_mut().expect("checked above").book(&bytes);
        }
        self.dev.check()
    }

    pub(super) fn encode_vertices(&mut self, enc: &mut wgpu::CommandEncoder) {
        if self.vertices_current {
            return;
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        if let Some(fg) = &self.followers {
            // Guides and followers: each guide point's frame, then every host vertex from
            // them (the fixed steps' blend, if on, is read through the followers' uniform).
            pass.set_pipeline(&fg.frames_pipe);
            pass.set_bind_group(0, &fg.frames_bg[self.cur], &[]);
            let (gx, gy) = groups(fg.guides());
            pass.dispatch_workgroups(gx, gy, 1);
            pass.set_pipeline(&fg.pipe);
            pass.set_bind_group(0, &fg.bg, &[]);
            let (gx, gy) = groups(fg.host_points());
            pass.dispatch_workgroups(gx, gy, 1);
        } else {
            match self.blend.as_ref().filter(|b| b.on) {
                Some(b) => {
                    pass.set_pipeline(&b.pipe);
                    pass.set_bind_group(0, &b.bg[self.cur], &[]);
                }
                None => {
                    pass.set_pipeline(&self.output);
                    pass.set_bind_group(0, &self.output_bg[self.cur], &[]);
                }
            }
            let (gx, gy) = groups(self.active_points);
            pass.dispatch_workgroups(gx, gy, 1);
        }
        drop(pass);
        self.encode_water_vertices(enc);
        self.vertices_current = true;
        self.wrote_vertices = true;
    }

    /// Pass write_water_vertices, where the host draws the particles and they exist.
    pub(super) fn encode_water_vertices(&mut self, enc: &mut wgpu::CommandEncoder) {
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
    pub(super) fn submit(&mut self, enc: wgpu::CommandEncoder) {
        let wrote = std::mem::take(&mut self.wrote_vertices);
        self.dev.submit(enc.finish(), wrote);
    }

    /// Whether the host draws straight from the vertex buffer (a host-shared device): then
    /// every step writes it.
    pub(super) fn shares_vertices(&self) -> bool {
        #[cfg(feature = "vulkan")]
        return self.dev.shared.is_some();
        #[cfg(not(feature = "vulkan"))]
        false
    }
}

/// Where drops that meet coalesce: the pile cell, m, the fixed-point unit of a drop's offset in
/// it (`cpu/piles.rs`'s `cell * POSITION_UNIT`), and their inverses, computed as the CPU
/// computes them; all 0 where drops do not coalesce.
fn pile_scale(p: &SimParams) -> [f32; 4] {
    if !p.coalesces() {
        return [0.0; 4];
    }
    let cell = p.water.pile_cell;
    let unit = cell * crate::cpu::piles::POSITION_UNIT;
    [cell, 1.0 / cell, unit, 1.0 / unit]
}
