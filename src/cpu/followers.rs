//! Copy-to-host output with guides and followers: pass `guide_frames` gathers each simulated
//! guide point's position, wetness and frame from the rows into columns, a row of eight guides
//! at a time ([`guide_frame_lanes`]), then pass `write_followers` writes every host strand from
//! them (`follower_output.rs`). A guide follows itself and is written exactly as simulated.
//! Both passes split across the worker pool.

use super::guide_columns::GuideColumns;
use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::follow::head_quat;
use crate::physics::follow_lanes::{guide_frame_lanes, splat_quat};
use crate::physics::followers::Followers;
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::roots::RootFrame;
use glam::Quat;
use rayon::prelude::*;
use std::sync::Mutex;

/// Host strands (or guides) per task.
pub(super) const STRANDS_PER_TASK: usize = 512;

/// The followers' output state: the binding data, how the output is posed now, and the
/// guide points gathered for the last output (kept: no allocation once grown).
#[derive(Debug)]
pub struct CpuFollowers {
    /// Bindings and rest pose.
    pub data: Followers,
    /// The head's rotation the offsets turn with.
    pub head: Quat,
    /// How far the output has moved from `data.from` to `data.follow`, 0..=1.
    pub blend: f32,
    /// Skinned roots only (else empty): every host strand's root frame as the output shows it.
    pub roots: Vec<RootFrame>,
    /// Each guide point's position, wetness, frame and rest position (guide-groom order).
    points: Mutex<GuideColumns>,
}

/// A buffer shared by tasks that each write their own disjoint range of it.
pub(super) struct Shared<T>(pub(super) *mut T);
// SAFETY: tasks write disjoint ranges (one per strand or guide); the buffer outlives them
// (they are joined before the writer returns).
unsafe impl<T> Sync for Shared<T> {}

/// Runs `task(t)` for `t` in `0..tasks`, on the pool when there is one.
pub(super) fn for_tasks(pool: Option<&super::pool::Pool>, tasks: usize, task: impl Fn(usize) + Sync + Send) {
    match pool {
        Some(p) => p.install(|| (0..tasks).into_par_iter().for_each(task)),
        None => (0..tasks).for_each(task),
    }
}

impl CpuFollowers {
    /// Followers from `data`, posed at rest.
    pub fn new(data: Followers) -> Self {
        CpuFollowers {
            data,
            head: Quat::IDENTITY,
            blend: 1.0,
            roots: Vec::new(),
            points: Mutex::new(GuideColumns::default()),
        }
    }

    /// Writes every host strand's attributes into `dst` (`host points * stride` floats) from
    /// the first `guides` guides' rows (`state`, `wet`), blended from `kept` by its factor
    /// where the fixed steps' output blend is on.
    #[allow(clippy::too_many_arguments)]
    pub fn write_vertices(
        &self,
        lay: &Layout,
        state: &[StateRow],
        wet: &[Lane],
        kept: Option<(&[L3], f32)>,
        guides: usize,
        attrs: VertexAttributes,
        pool: Option<&super::pool::Pool>,
        dst: &mut [f32],
    ) {
        let fl = &self.data;
        assert_eq!(dst.len(), fl.rest.len() * attrs.stride(), "one vertex per host point");
        let mut points = self.points.lock().unwrap_or_else(|e| e.into_inner());
        points.resize(&fl.spans);
        let avx2 = super::avx2::cpu_has_avx2();
        self.guide_frames(lay, state, wet, kept, guides, pool, avx2, &mut points);
        super::follower_output::write_followers(fl, &points, self.blend, &self.roots, attrs, pool, dst);
    }

    /// Pass guide_frames: guides `0..guides`' points into `out`, block by block of the layout:
    /// a row is point `j` of eight guides, read as lanes, each frame from the row before and
    /// the guide's starting rotation (the head's, or with skinned roots its own root's). `avx2`:
    /// compiled for AVX2 (only where the CPU has it), else the baseline; the same bits.
    #[allow(clippy::too_many_arguments)]
    fn guide_frames(
        &self,
        lay: &Layout,
        state: &[StateRow],
        wet: &[Lane],
        kept: Option<(&[L3], f32)>,
        guides: usize,
        pool: Option<&super::pool::Pool>,
        avx2: bool,
        out: &mut GuideColumns,
    ) {
        let data: &mut [f32] = bytemuck::cast_slice_mut(&mut out.lines);
        let job = FramesJob {
            fl: self,
            lay,
            state,
            wet,
            kept,
            guides: guides.min(self.data.spans.len()),
            base: &out.base,
            width: &out.width,
            len: data.len(),
            data: Shared(data.as_mut_ptr()),
            avx2,
        };
        const BLOCKS_PER_TASK: usize = STRANDS_PER_TASK / W;
        let task =
            |t: usize| frames_blocks_best(&job, t * BLOCKS_PER_TASK..((t + 1) * BLOCKS_PER_TASK).min(lay.blocks));
        for_tasks(pool, lay.blocks.div_ceil(BLOCKS_PER_TASK), task);
    }
}

/// What pass guide_frames reads and where it writes.
struct FramesJob<'a> {
    fl: &'a CpuFollowers,
    lay: &'a Layout,
    state: &'a [StateRow],
    wet: &'a [Lane],
    kept: Option<(&'a [L3], f32)>,
    guides: usize,
    base: &'a [usize],
    width: &'a [usize],
    /// The columns' floats: `len` of them from `data`.
    data: Shared<f32>,
    len: usize,
    avx2: bool,
}

super::avx2::avx2_or_base!(
    /// Blocks `blocks` of pass guide_frames, compiled for AVX2 where the CPU has it (a closure
    /// on the pool is compiled for the baseline: the frames' square roots and divides then ran
    /// one lane at a time, a quarter of the output's time at 25% guides).
    fn frames_blocks_best(job: &FramesJob, blocks: std::ops::Range<usize>) => frames_blocks
);

#[inline(always)]
fn frames_blocks(job: &FramesJob, blocks: std::ops::Range<usize>) {
    let (lay, fl, state) = (job.lay, &job.fl.data, job.state);
    let head = head_quat(job.fl.head);
    for b in blocks {
        // Each lane's guide (`None`: not a simulated guide now) and its span.
        let lanes: [Option<(usize, crate::physics::followers::GuideSpan)>; W] = std::array::from_fn(|l| {
            let g = lay.strand_of_slot[b * W + l] as usize;
            (g < job.guides).then(|| (g, fl.spans[g]))
        });
        let rows = lanes.iter().flatten().map(|(_, s)| s.count as usize).max().unwrap_or(0);
        let mut hq = splat_quat(head);
        if !job.fl.roots.is_empty() {
            for (l, (_, s)) in lanes.iter().enumerate().filter_map(|(l, g)| g.map(|g| (l, g))) {
                let q = job.fl.roots[s.host as usize].rotation.to_array();
                for (c, v) in hq.iter_mut().zip(q) {
                    c[l] = v;
                }
            }
        }
        // Each lane's guide block: where its columns start and their distance, checked once
        // for the guide's last point (then every store below is in bounds).
        let cols: [Option<(usize, usize, usize)>; W] = std::array::from_fn(|l| {
            lanes[l].map(|(g, s)| {
                let (base, width) = (job.base[g], job.width[g]);
                assert!(base + (GuideColumns::PLANES - 1) * width + (s.count as usize) <= job.len);
                (base, width, s.count as usize)
            })
        });
        let (mut x_prev, mut rest_prev) = (L3::ZERO, L3::ZERO);
        for j in 0..rows {
            let r = b * lay.rows + j;
            let x = match job.kept {
                Some((from, a)) => from[r].toward(&state[r].x, a),
                None => state[r].x,
            };
            let mut rest = L3::ZERO;
            for (l, lane) in lanes.iter().enumerate() {
                if let Some((_, s)) = lane.filter(|(_, s)| j < s.count as usize) {
                    rest.set(l, fl.rest[s.rest as usize + j]);
                }
            }
            let q = if j == 0 {
                hq
            } else {
                guide_frame_lanes(&hq, &rest_prev, &rest, &x_prev, &x)
            };
            let w = job.wet.get(r).copied().unwrap_or([0.0; W]);
            for (l, col) in cols.iter().enumerate() {
                let Some((base, width, _)) = col.filter(|&(_, _, n)| j < n) else {
                    continue;
                };
                let values = [
                    x.x[l], x.y[l], x.z[l], w[l], q[0][l], q[1][l], q[2][l], q[3][l], rest.x[l], rest.y[l], rest.z[l],
                ];
                for (c, v) in values.into_iter().enumerate() {
                    // SAFETY: `base + c * width + j` is below `len` (checked for the guide's
                    // last point above), and guide `g`'s block is written by this task only
                    // (its block of the layout is).
                    unsafe { *job.data.0.add(base + c * width + j) = v };
                }
            }
            (x_prev, rest_prev) = (x, rest);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::follow::guide_frame_at;
    use crate::physics::followers::GuideSpan;
    use glam::Vec3;

    /// Pass guide_frames, a row of eight guides at a time, gathers what the one-point law
    /// computes for each guide point, bit for bit: ragged guides (some shorter than others in
    /// their block), a turned head, moved points, wetness, a blend from kept positions, and only
    /// the first `guides` guides simulated; compiled for AVX2 and for the baseline.
    #[test]
    fn guide_frames_gather_the_one_point_frames() {
        let counts: Vec<u32> = (0..21).map(|s| 2 + (s * 7) % 19).collect();
        let (groom, lay, state, wet) = super::super::layout::fixture::ragged(&counts, 17, (1.0, 0.2));
        let kept: Vec<L3> = state.iter().map(|r| r.x.toward(&L3::ZERO, 0.1)).collect();
        let spans: Vec<GuideSpan> = (0..counts.len())
            .map(|s| GuideSpan {
                first: groom.strand_first[s],
                rest: groom.strand_first[s],
                count: counts[s],
                host: (s as u32 * 5) % 21,
            })
            .collect();
        let mut fl = CpuFollowers::new(Followers {
            strand_first: groom.strand_first.clone(),
            rest: groom.positions().to_vec(),
            spans: spans.clone(),
            follow: Vec::new(),
            from: Vec::new(),
            clump: 0.8,
            root_points: Vec::new(),
        });
        fl.head = Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-0.3);
        // Skinned roots: each guide starts from its host strand's root rotation.
        let frames: Vec<RootFrame> = (0..21)
            .map(|s| RootFrame {
                position: Vec3::ZERO,
                rotation: Quat::from_rotation_z(0.1 * s as f32) * Quat::from_rotation_x(0.05 * s as f32),
            })
            .collect();
        let cases = [
            (None, 21, false),
            (Some((&kept[..], 0.6f32)), 13, false),
            (None, 21, true),
        ];
        let avx2 = crate::cpu::avx2::cpu_has_avx2();
        for ((kept, guides, roots), avx2) in cases.into_iter().flat_map(|c| [(c, false), (c, avx2)]) {
            fl.roots = if roots { frames.clone() } else { Vec::new() };
            let head = |s: &GuideSpan| match roots {
                false => head_quat(fl.head),
                true => head_quat(frames[s.host as usize].rotation),
            };
            let mut cols = GuideColumns::default();
            cols.resize(&spans);
            fl.guide_frames(&lay, &state, &wet, kept, guides, None, avx2, &mut cols);
            for (g, span) in spans.iter().enumerate().take(guides) {
                let (b, l) = lay.lane_of(g);
                let x = |j: u32| {
                    let r = b * lay.rows + j as usize;
                    match kept {
                        Some((from, a)) => from[r].get(l) + a * (state[r].x.get(l) - from[r].get(l)),
                        None => state[r].x.get(l),
                    }
                };
                for j in 0..span.count {
                    let frame = guide_frame_at(*span, j, &fl.data.rest, head(span), |p| x(p - span.first));
                    let want = (
                        x(j),
                        wet[b * lay.rows + j as usize][l],
                        frame,
                        fl.data.rest[(span.rest + j) as usize],
                    );
                    let got = cols.point((span.first + j) as usize);
                    let bits = |p: (Vec3, f32, glam::Vec4, Vec3)| {
                        [
                            p.0.to_array(),
                            [p.1; 3],
                            [p.2.x, p.2.y, p.2.z],
                            [p.2.w, 0.0, 0.0],
                            p.3.to_array(),
                        ]
                        .concat()
                        .iter()
                        .map(|v| v.to_bits())
                        .collect::<Vec<_>>()
                    };
                    assert_eq!(bits(got), bits(want), "guide {g} point {j}, avx2 {avx2}");
                }
            }
        }
    }
}
