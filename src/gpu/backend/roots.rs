//! Skinned roots on the GPU (`physics/roots.rs`, `roots.wgsl`): every strand's root frames at
//! the start and the end of the step, uploaded once a step; each pinned point's rest offset
//! from its root; pass `pin_roots` before each substep's hair kernel, and pass `carry_roots`
//! submitted on its own when strands teleport or a reset hangs them from their frames.
//! Nothing here exists without skinned roots.

use super::super::buffers::{self as b, groups, CarryGpu, PinGpu, RootPairGpu, RootsUniformGpu, STORAGE};
use super::super::pipelines::{self as pl, SceneConsts, Slot};
use crate::physics::roots::RootFrame;
use glam::Vec3;

/// The roots' buffers and passes.
#[derive(Debug)]
pub(super) struct SkinnedRoots {
    /// Per strand, host order.
    pairs: wgpu::Buffer,
    pair_data: Vec<RootPairGpu>,
    pins: u32,
    /// Strands to carry (room for all: a reset carries every one).
    carries: wgpu::Buffer,
    carry_data: Vec<CarryGpu>,
    /// One slot per substep (`a`), then the carry's (`count`), `stride` apart.
    uniform: wgpu::Buffer,
    uniform_bytes: Vec<u8>,
    stride: u64,
    most_sub: usize,
    /// Each strand's first and last point.
    spans: Vec<[u32; 2]>,
    pin_pipe: wgpu::ComputePipeline,
    carry_pipe: wgpu::ComputePipeline,
    /// Over state `i` (the carry's); the pin pass binds either.
    bg: [wgpu::BindGroup; 2],
}

/// The inputs the passes bind that the backend owns.
pub(super) struct RootsInputs<'a> {
    /// Rest positions, host order (head space).
    pub rest: &'a [Vec3],
    pub strand_first: &'a [u32],
    pub pinned: &'a [bool],
    /// The point records the hair kernels read (their pinned rest positions are overwritten).
    pub points: &'a wgpu::Buffer,
    pub state: &'a [wgpu::Buffer; 2],
    pub most_sub: usize,
    pub align: u64,
}

fn pos4(v: Vec3) -> [f32; 4] {
    v.extend(0.0).to_array()
}

impl SkinnedRoots {
    /// Buffers for `at`'s strands, every root at rest, and the two passes.
    pub(super) fn new(d: &wgpu::Device, q: &wgpu::Queue, c: SceneConsts, at: RootsInputs) -> SkinnedRoots {
        let strands = at.strand_first.len() - 1;
        let spans: Vec<[u32; 2]> = (0..strands)
            .map(|s| [at.strand_first[s], at.strand_first[s + 1] - 1])
            .collect();
        let mut pins = Vec::new();
        let mut pair_data = Vec::with_capacity(strands);
        for (s, span) in spans.iter().enumerate() {
            let r0 = at.rest[span[0] as usize];
            let rest = RootFrame::at_rest(r0);
            pair_data.push(RootPairGpu {
                from_pos: pos4(rest.position),
                from_rot: rest.rotation.to_array(),
                to_pos: pos4(rest.position),
                to_rot: rest.rotation.to_array(),
            });
            for i in span[0]..=span[1] {
                if at.pinned[i as usize] {
                    pins.push(PinGpu {
                        offset: pos4(at.rest[i as usize] - r0),
                        at: [i, s as u32, 0, 0],
                    });
                }
            }
        }
        let pair_size = std::mem::size_of::<RootPairGpu>() as u64;
        let pairs = b::buffer(d, "root_pairs", pair_size * strands as u64, STORAGE);
        q.write_buffer(&pairs, 0, bytemuck::cast_slice(&pair_data));
        let pin_buf = b::buffer(d, "pins", (std::mem::size_of::<PinGpu>() * pins.len()) as u64, STORAGE);
        q.write_buffer(&pin_buf, 0, bytemuck::cast_slice(&pins));
        let carries = b::buffer(
            d,
            "carries",
            (std::mem::size_of::<CarryGpu>() * strands) as u64,
            STORAGE,
        );
        let rec = std::mem::size_of::<RootsUniformGpu>() as u64;
        let stride = rec.next_multiple_of(at.align);
        let uniform = b::buffer(
            d,
            "roots_uniform",
            stride * (at.most_sub as u64 + 1),
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let layout = pl::layout(
            d,
            "roots",
            &[
                Slot::UniformDynamic,
                Slot::Read,
                Slot::Read,
                Slot::ReadWrite,
                Slot::Read,
                Slot::ReadWrite,
            ],
        );
        let mk = |i: usize| {
            pl::bind(
                d,
                "roots",
                &layout,
                &[&uniform, &pairs, &pin_buf, at.points, &carries, &at.state[i]],
                Some((0, rec)),
            )
        };
        let bg = [mk(0), mk(1)];
        let module = pl::module(d, "roots", &pl::roots_source(c));
        let mut pipes = pl::pipelines(d, &module, &[&layout], &["pin_roots", "carry_roots"]);
        let carry_pipe = pipes.remove(1);
        let pin_pipe = pipes.remove(0);
        SkinnedRoots {
            pairs,
            pair_data,
            pins: pins.len() as u32,
            carries,
            carry_data: Vec::with_capacity(strands),
            uniform,
            uniform_bytes: Vec::new(),
            stride,
            most_sub: at.most_sub,
            spans,
            pin_pipe,
            carry_pipe,
            bg,
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        (self.pairs.size() + self.carries.size() + self.uniform.size()) as usize + self.pins as usize * 32
    }

    /// Moves the roots from `from` to `to` (one per host strand) over the next step.
    pub(super) fn place(&mut self, q: &wgpu::Queue, from: &[RootFrame], to: &[RootFrame]) {
        for ((p, f), t) in self.pair_data.iter_mut().zip(from).zip(to) {
            *p = RootPairGpu {
                from_pos: pos4(f.position),
                from_rot: f.rotation.to_array(),
                to_pos: pos4(t.position),
                to_rot: t.rotation.to_array(),
            };
        }
        q.write_buffer(&self.pairs, 0, bytemuck::cast_slice(&self.pair_data));
    }

    /// Writes how far through the step each of `n_sub` substeps ends.
    pub(super) fn write_substeps(&mut self, q: &wgpu::Queue, n_sub: usize) {
        let bytes = &mut self.uniform_bytes;
        bytes.clear();
        bytes.resize(self.stride as usize * n_sub, 0);
        for s in 0..n_sub {
            let u = RootsUniformGpu {
                a: (s + 1) as f32 / n_sub as f32,
                ..Default::default()
            };
            let at = s * self.stride as usize;
            bytes[at..at + std::mem::size_of::<RootsUniformGpu>()].copy_from_slice(bytemuck::bytes_of(&u));
        }
        q.write_buffer(&self.uniform, 0, bytes);
    }

    /// Pass pin_roots of substep `s`.
    pub(super) fn encode_pin(&self, pass: &mut wgpu::ComputePass, s: usize) {
        if self.pins == 0 {
            return;
        }
        pass.set_pipeline(&self.pin_pipe);
        pass.set_bind_group(0, &self.bg[0], &[(s as u64 * self.stride) as u32]);
        let (gx, gy) = groups(self.pins);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// Pass carry_roots over state `cur`: host strands `strands` from `from` to `to`.
    pub(super) fn encode_carry(
        &mut self,
        q: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        cur: usize,
        strands: &[u32],
        from: &[RootFrame],
        to: &[RootFrame],
    ) {
        self.carry_data.clear();
        for ((&s, f), t) in strands.iter().zip(from).zip(to) {
            let [first, last] = self.spans[s as usize];
            self.carry_data.push(CarryGpu {
                from_pos: pos4(f.position),
                from_rot: f.rotation.to_array(),
                to_pos: pos4(t.position),
                to_rot: t.rotation.to_array(),
                span: [first, last, 0, 0],
            });
        }
        q.write_buffer(&self.carries, 0, bytemuck::cast_slice(&self.carry_data));
        let u = RootsUniformGpu {
            count: strands.len() as u32,
            ..Default::default()
        };
        let slot = self.most_sub as u64 * self.stride;
        q.write_buffer(&self.uniform, slot, bytemuck::bytes_of(&u));
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.carry_pipe);
        pass.set_bind_group(0, &self.bg[cur], &[slot as u32]);
        let (gx, gy) = groups(strands.len() as u32);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}
