//! Guides and followers on the GPU: the host's rest pose, each host strand's bindings and the
//! guides' spans in storage buffers, the pose in a uniform, and passes `guide_frames`
//! (`guide_frames.wgsl`: each guide point's position, wetness and frame) and
//! `write_followers` (`write_followers.wgsl`: every host vertex), which replace
//! `write_vertices`. Also the
//! simulated fraction (the hair passes dispatch over the first guides only) and the seeding
//! of guides that start to be simulated. With skinned roots, every host strand's root frame
//! as the output shows it (`follow_roots`, uploaded with each pose). Nothing here exists in a
//! scene without guides.

use super::super::buffers::{self as b, FollowStrandGpu, FollowUniformGpu, StateGpu, STORAGE};
use super::super::pipelines::{self as pl, Slot};
use super::GpuBackend;
use crate::error::{Error, Result};
use crate::physics::followers::{Follow, Followers};
use crate::physics::roots::RootFrame;
use glam::{Quat, Vec3};

/// The followers' buffers, uniform, pipelines and bind groups (the frames' one per current
/// state buffer).
#[derive(Debug)]
pub(super) struct FollowersGpu {
    uniform: wgpu::Buffer,
    strands: wgpu::Buffer,
    rest: wgpu::Buffer,
    spans: wgpu::Buffer,
    /// Per guide point: position and wetness, frame, rest position (three vec4).
    points: wgpu::Buffer,
    /// Skinned roots only: per host strand, its root frame's position and rotation (two vec4).
    roots: Option<wgpu::Buffer>,
    /// `follow_roots`' words as last written (reused: no allocation once grown).
    root_words: Vec<[f32; 4]>,
    frames_layout: wgpu::BindGroupLayout,
    pub(super) frames_pipe: wgpu::ComputePipeline,
    pub(super) frames_bg: [wgpu::BindGroup; 2],
    pub(super) pipe: wgpu::ComputePipeline,
    pub(super) bg: wgpu::BindGroup,
    /// The uniform's contents (written whole when any part changes).
    pose: FollowUniformGpu,
}

impl FollowersGpu {
    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        let roots = self.roots.as_ref().map_or(0, |r| r.size());
        (self.uniform.size() + self.strands.size() + self.rest.size() + self.spans.size() + self.points.size() + roots)
            as usize
    }

    /// Host vertices written.
    pub(super) fn host_points(&self) -> u32 {
        self.pose.host_points
    }

    /// Guides gathered.
    pub(super) fn guides(&self) -> u32 {
        self.pose.guides
    }
}

/// Each host strand's record: its span and both bindings (`from` the same as `follow` when
/// settled).
fn strand_records(f: &Followers) -> Vec<FollowStrandGpu> {
    let pad = |a: [u32; 3]| [a[0], a[1], a[2], 0];
    let padf = |a: [f32; 3]| [a[0], a[1], a[2], 0.0];
    (0..f.follow.len())
        .map(|h| {
            let now = f.follow[h];
            let was: Follow = f.from.get(h).copied().unwrap_or(now);
            FollowStrandGpu {
                first: f.strand_first[h],
                count: f.strand_first[h + 1] - f.strand_first[h],
                root_points: f.root_points.get(h).copied().unwrap_or(0),
                pad1: 0,
                guides: pad(now.guides),
                weights: padf(now.weights),
                from_guides: pad(was.guides),
                from_weights: padf(was.weights),
            }
        })
        .collect()
}

impl GpuBackend {
    /// Makes the followers' output (first call) or replaces the bindings (later calls).
    pub fn set_followers(&mut self, f: &Followers) -> Result<()> {
        self.dev.check()?;
        let records = strand_records(f);
        if let Some(fg) = &mut self.followers {
            self.dev
                .queue
                .write_buffer(&fg.strands, 0, bytemuck::cast_slice(&records));
            fg.pose.has_from = (!f.from.is_empty()) as u32;
            self.dev
                .queue
                .write_buffer(&fg.uniform, 0, bytemuck::bytes_of(&fg.pose));
            self.vertices_current = false;
            return Ok(());
        }
        let d = &self.dev.device;
        let max = self.dev.limits.max_storage_buffer_binding_size;
        let rest_bytes = f.rest.len() as u64 * 16;
        if rest_bytes > max {
            return Err(Error::Capacity(format!(
                "{} host points need {rest_bytes} bytes of follower rest positions; the device allows {max} per buffer (the CPU backend has no such limit)",
                f.rest.len()
            )));
        }
        let strands = b::buffer(
            d,
            "follow_strands",
            std::mem::size_of_val(records.as_slice()) as u64,
            STORAGE,
        );
        self.dev.queue.write_buffer(&strands, 0, bytemuck::cast_slice(&records));
        let mut rest_words = Vec::with_capacity(f.rest.len());
        for h in 0..f.follow.len() {
            for k in f.strand_first[h]..f.strand_first[h + 1] {
                let p = f.rest[k as usize];
                rest_words.push([p.x, p.y, p.z, f32::from_bits(h as u32)]);
            }
        }
        let rest = b::buffer(d, "follow_rest", rest_bytes, STORAGE);
        self.dev.queue.write_buffer(&rest, 0, bytemuck::cast_slice(&rest_words));
        let span_words: Vec<[u32; 4]> = f.spans.iter().map(|s| [s.first, s.rest, s.count, s.host]).collect();
        let spans = b::buffer(d, "guide_spans", (span_words.len().max(1) * 16) as u64, STORAGE);
        self.dev
            .queue
            .write_buffer(&spans, 0, bytemuck::cast_slice(&span_words));
        let uniform = b::buffer(
            d,
            "follow_uniform",
            std::mem::size_of::<FollowUniformGpu>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let pose = FollowUniformGpu {
            head: [0.0, 0.0, 0.0, 1.0],
            blend: 1.0,
            clump: f.clump,
            host_points: f.rest.len() as u32,
            has_from: (!f.from.is_empty()) as u32,
            guides: self.active_strands,
            ..Default::default()
        };
        self.dev.queue.write_buffer(&uniform, 0, bytemuck::bytes_of(&pose));
        let points = b::buffer(d, "guide_points", self.points.max(1) as u64 * 48, STORAGE);
        let roots =
            (!f.root_points.is_empty()).then(|| b::buffer(d, "follow_roots", f.follow.len() as u64 * 32, STORAGE));
        // Without skinned roots the passes never read `follow_roots`: the rest pose stands in
        // for it in the bind groups, so no buffer is made for it.
        let roots_bound = roots.as_ref().unwrap_or(&rest);
        use Slot::{Read, ReadWrite, Uniform};
        let frames_layout = pl::layout(d, "guide_frames", &[Uniform, Read, Read, Read, Read, ReadWrite, Read]);
        let module = pl::module(d, "guide_frames", &pl::guide_frames_source(self.consts));
        let frames_pipe = pl::pipelines(d, &module, &[&frames_layout], &["guide_frames"]).remove(0);
        let layout = pl::layout(
            d,
            "write_followers",
            &[Uniform, Uniform, Read, ReadWrite, Read, Read, Read, Read, Read],
        );
        let module = pl::module(d, "write_followers", &pl::write_followers_source(self.consts));
        let pipe = pl::pipelines(d, &module, &[&layout], &["write_followers"]).remove(0);
        let bg = pl::bind(
            d,
            "write_followers",
            &layout,
            &[
                &self.params_buf,
                &uniform,
                &self.status,
                &self.vertices,
                &strands,
                &rest,
                &spans,
                &points,
                roots_bound,
            ],
            None,
        );
        let mut fg = FollowersGpu {
            uniform,
            strands,
            rest,
            spans,
            points,
            roots,
            root_words: Vec::new(),
            frames_layout,
            frames_pipe,
            frames_bg: [bg.clone(), bg.clone()],
            pipe,
            bg,
            pose,
        };
        fg.frames_bg = [0, 1].map(|i| self.bind_frames(&fg, i));
        self.followers = Some(fg);
        self.vertices_current = false;
        self.dev.check()
    }

    /// Pass guide_frames' bind group over state buffer `i` (the kept state of the fixed steps'
    /// blend where it exists, else the state again, never read then).
    fn bind_frames(&self, fg: &FollowersGpu, i: usize) -> wgpu::BindGroup {
        let from = self.blend.as_ref().map_or(&self.state[i], |bl| bl.from());
        pl::bind(
            &self.dev.device,
            "guide_frames",
            &fg.frames_layout,
            &[
                &fg.uniform,
                &self.state[i],
                from,
                &fg.spans,
                &fg.rest,
                &fg.points,
                fg.roots.as_ref().unwrap_or(&fg.rest),
            ],
            None,
        )
    }

    /// Binds the fixed steps' kept state (made after the followers) into the followers' pass.
    pub(super) fn rebind_followers(&mut self) {
        if let Some(fg) = self.followers.take() {
            let frames_bg = [0, 1].map(|i| self.bind_frames(&fg, i));
            self.followers = Some(FollowersGpu { frames_bg, ..fg });
        }
    }

    /// The followers' pose: the head's rotation, the blend between bindings, and with skinned
    /// roots every host strand's root frame (else empty).
    pub fn pose_followers(&mut self, head: Quat, blend: f32, roots: &[RootFrame]) {
        if let Some(fg) = &mut self.followers {
            fg.pose.head = head.to_array();
            fg.pose.blend = blend;
            if let (Some(buf), false) = (&fg.roots, roots.is_empty()) {
                fg.root_words.clear();
                let words = roots
                    .iter()
                    .flat_map(|r| [r.position.extend(0.0).to_array(), r.rotation.to_array()]);
                fg.root_words.extend(words);
                self.dev
                    .queue
                    .write_buffer(buf, 0, bytemuck::cast_slice(&fg.root_words));
                fg.pose.roots = 1;
            }
            self.dev
                .queue
                .write_buffer(&fg.uniform, 0, bytemuck::bytes_of(&fg.pose));
            self.vertices_current = false;
        }
    }

    /// The fixed steps' output blend as the followers read the guides (`None`: off).
    pub(super) fn followers_kept(&mut self, a: Option<f32>) {
        if let Some(fg) = &mut self.followers {
            fg.pose.kept = a.is_some() as u32;
            fg.pose.kept_a = a.unwrap_or(0.0);
            self.dev
                .queue
                .write_buffer(&fg.uniform, 0, bytemuck::bytes_of(&fg.pose));
        }
    }

    /// Steps only the first `n` strands from the next step on.
    pub fn set_active_strands(&mut self, n: usize) {
        let n = n.min(self.strand_first.len() - 1);
        self.active_strands = n as u32;
        self.active_points = self.strand_first[n];
        if let Some(v) = &mut self.volume {
            v.points = self.active_points;
        }
        if let Some(fg) = &mut self.followers {
            fg.pose.guides = self.active_strands;
            self.dev
                .queue
                .write_buffer(&fg.uniform, 0, bytemuck::bytes_of(&fg.pose));
            self.vertices_current = false;
        }
    }

    /// Sets strands from `first` on to `x`, `v` and wetness `wet` (their points in order).
    pub fn seed_strands(&mut self, first: u32, x: &[Vec3], v: &[Vec3], wet: &[f32]) -> Result<()> {
        self.dev.check()?;
        let at = self.strand_first[first as usize] as u64;
        let recs: Vec<StateGpu> = (0..x.len())
            .map(|k| StateGpu {
                x: [x[k].x, x[k].y, x[k].z, wet[k]],
                v: [v[k].x, v[k].y, v[k].z, 0.0],
            })
            .collect();
        self.dev
            .queue
            .write_buffer(&self.state[self.cur], at * 32, bytemuck::cast_slice(&recs));
        self.bdf2 = crate::physics::bdf2::Bdf2Clock::default();
        self.vertices_current = false;
        Ok(())
    }
}
