//! Copy-to-host output with guides and followers: pass `guide_frames` gathers each simulated
//! guide point's position, wetness and frame from the rows ([`guide_frame_at`]), then pass
//! `write_followers` writes every host strand from them ([`output_point`]; a guide follows
//! itself and is written exactly as simulated). Both split across the worker pool.

use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::follow::{guide_frame_at, head_quat, output_point, tangent, GuidePoint};
use crate::physics::followers::Followers;
use crate::physics::lanes::{Lane, L3};
use glam::{Quat, Vec3, Vec4};
use rayon::prelude::*;
use std::sync::Mutex;

/// Host strands (or guides) per task.
const STRANDS_PER_TASK: usize = 512;

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
    /// Each guide point's position, wetness and frame (guide-groom order).
    points: Mutex<Vec<GuidePoint>>,
}

/// A buffer shared by tasks that each write their own disjoint range of it.
struct Shared<T>(*mut T);
// SAFETY: tasks write disjoint ranges (one per strand or guide); the buffer outlives them
// (they are joined before the writer returns).
unsafe impl<T> Sync for Shared<T> {}

/// Runs `task(t)` for `t` in `0..tasks`, on the pool when there is one.
fn for_tasks(pool: Option<&super::pool::Pool>, tasks: usize, task: impl Fn(usize) + Sync + Send) {
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
            points: Mutex::new(Vec::new()),
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
        points.resize(
            fl.spans.last().map_or(0, |s| (s.first + s.count) as usize),
            (Vec3::ZERO, 0.0, Vec4::ZERO, Vec3::ZERO),
        );
        self.guide_frames(lay, state, wet, kept, guides, pool, &mut points);
        self.write_followers(&points, attrs, pool, dst);
    }

    /// Pass guide_frames: guides `0..guides`' points into `out` (guide-groom order).
    #[allow(clippy::too_many_arguments)]
    fn guide_frames(
        &self,
        lay: &Layout,
        state: &[StateRow],
        wet: &[Lane],
        kept: Option<(&[L3], f32)>,
        guides: usize,
        pool: Option<&super::pool::Pool>,
        out: &mut [GuidePoint],
    ) {
        let fl = &self.data;
        let head = head_quat(self.head);
        let guides = guides.min(fl.spans.len());
        let len = out.len();
        let out = Shared(out.as_mut_ptr());
        let task = |t: usize| {
            let out = &out;
            for g in t * STRANDS_PER_TASK..((t + 1) * STRANDS_PER_TASK).min(guides) {
                let span = fl.spans[g];
                let (b, l) = lay.lane_of(g);
                let mut prev = Vec3::ZERO;
                for j in 0..span.count {
                    let r = b * lay.rows + j as usize;
                    let x = state[r].x.get(l);
                    let x = match kept {
                        Some((from, a)) => {
                            let p = from[r].get(l);
                            p + a * (x - p)
                        }
                        None => x,
                    };
                    let frame = guide_frame_at(span, j, &fl.rest, head, |p| if p == span.first + j { x } else { prev });
                    let k = (span.first + j) as usize;
                    assert!(k < len);
                    let rest = fl.rest[(span.rest + j) as usize];
                    // SAFETY: `k` is inside `out` (asserted), and guide `g`'s points are
                    // written by this task only.
                    unsafe { *out.0.add(k) = (x, wet.get(r).map_or(0.0, |w| w[l]), frame, rest) };
                    prev = x;
                }
            }
        };
        for_tasks(pool, guides.div_ceil(STRANDS_PER_TASK), task);
    }

    /// Pass write_followers: every host strand from the guide points, in the host's order (its
    /// rest pose, bindings and vertices are read and written in memory order; a groom's
    /// neighbouring strands are near each other in it, so they read the same guides from
    /// cache), each strand's vertices written once, in place.
    fn write_followers(
        &self,
        points: &[GuidePoint],
        attrs: VertexAttributes,
        pool: Option<&super::pool::Pool>,
        dst: &mut [f32],
    ) {
        let fl = &self.data;
        let strands = fl.strand_first.len() - 1;
        let at = |p: u32| points[p as usize];
        let (stride, pos, tan, wetness) = (
            attrs.stride(),
            attrs.offset(VertexAttributes::POSITION),
            attrs.offset(VertexAttributes::TANGENT),
            attrs.offset(VertexAttributes::WETNESS),
        );
        let out = Shared(dst.as_mut_ptr());
        let task = |t: usize| {
            let out = &out;
            let mut pts: Vec<(Vec3, f32)> = Vec::with_capacity(crate::groom::MAX_POINTS_PER_STRAND);
            for h in t * STRANDS_PER_TASK..((t + 1) * STRANDS_PER_TASK).min(strands) {
                let first = fl.strand_first[h] as usize;
                let n = fl.strand_first[h + 1] as usize - first;
                pts.clear();
                pts.extend((0..n as u32).map(|i| output_point(fl, h, i, self.blend, &at)));
                // SAFETY: strand `h`'s vertices lie inside `dst` (asserted by the caller: one
                // vertex per host point), and only this task writes them.
                let v = unsafe { std::slice::from_raw_parts_mut(out.0.add(first * stride), n * stride) };
                for (i, (&(x, w), v)) in pts.iter().zip(v.chunks_exact_mut(stride)).enumerate() {
                    if let Some(o) = pos {
                        v[o..o + 3].copy_from_slice(&x.to_array());
                    }
                    if let Some(o) = tan {
                        let a = pts[i.saturating_sub(1)].0;
                        let b = pts[(i + 1).min(n - 1)].0;
                        v[o..o + 3].copy_from_slice(&tangent(a, b).to_array());
                    }
                    if let Some(o) = wetness {
                        v[o] = w;
                    }
                }
            }
        };
        for_tasks(pool, strands.div_ceil(STRANDS_PER_TASK), task);
    }
}
