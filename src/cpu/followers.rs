//! Copy-to-host output with guides and followers: every host strand's vertices from the
//! simulated guides by [`crate::physics::followers::output_point`] (a guide follows itself
//! and is written exactly as simulated), strands split across the worker pool.

use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::followers::{output_point, tangent, Followers};
use crate::physics::lanes::{Lane, L3};
use glam::{Quat, Vec3};
use rayon::prelude::*;

/// Host strands per task.
const STRANDS_PER_TASK: usize = 512;

/// The followers' output state: the binding data and how the output is posed now.
#[derive(Debug)]
pub struct CpuFollowers {
    /// Bindings and rest pose.
    pub data: Followers,
    /// The head's rotation the offsets turn with.
    pub head: Quat,
    /// How far the output has moved from `data.from` to `data.follow`, 0..=1.
    pub blend: f32,
}

/// The host's vertex buffer, shared by the tasks: each writes only its own strands' vertices.
struct Dst(*mut f32);
// SAFETY: tasks write disjoint strand ranges; the buffer outlives them (joined before return).
unsafe impl Sync for Dst {}

impl CpuFollowers {
    /// Writes every host strand's attributes into `dst` (`host points * stride` floats) from
    /// the guides' rows (`state`, `wet`), blended from `kept` by its factor where the fixed
    /// steps' output blend is on.
    #[allow(clippy::too_many_arguments)]
    pub fn write_vertices(
        &self,
        lay: &Layout,
        state: &[StateRow],
        wet: &[Lane],
        kept: Option<(&[L3], f32)>,
        attrs: VertexAttributes,
        pool: Option<&super::pool::Pool>,
        dst: &mut [f32],
    ) {
        let fl = &self.data;
        let strands = fl.strand_first.len() - 1;
        assert_eq!(dst.len(), fl.rest.len() * attrs.stride(), "one vertex per host point");
        let at = |g: u32, j: u32| -> (Vec3, f32) {
            let (b, l) = lay.lane_of(g as usize);
            let r = b * lay.rows + j as usize;
            let x = state[r].x.get(l);
            let x = match kept {
                Some((from, a)) => {
                    let p = from[r].get(l);
                    p + a * (x - p)
                }
                None => x,
            };
            (x, wet.get(r).map_or(0.0, |w| w[l]))
        };
        let (stride, pos, tan, wetness) = (
            attrs.stride(),
            attrs.offset(VertexAttributes::POSITION),
            attrs.offset(VertexAttributes::TANGENT),
            attrs.offset(VertexAttributes::WETNESS),
        );
        let out = Dst(dst.as_mut_ptr());
        let task = |t: usize| {
            let out = &out;
            let mut pts: Vec<(Vec3, f32)> = Vec::with_capacity(crate::groom::MAX_POINTS_PER_STRAND);
            for h in t * STRANDS_PER_TASK..((t + 1) * STRANDS_PER_TASK).min(strands) {
                let first = fl.strand_first[h] as usize;
                let n = fl.strand_first[h + 1] as usize - first;
                pts.clear();
                pts.extend((0..n as u32).map(|i| output_point(fl, h, i, self.head, self.blend, &at)));
                for (i, &(x, w)) in pts.iter().enumerate() {
                    let mut v = [0.0f32; 7];
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
                    // SAFETY: vertex `first + i` of strand `h` lies inside `dst` (the assert
                    // above), and only this task writes strand `h`.
                    unsafe {
                        std::ptr::copy_nonoverlapping(v.as_ptr(), out.0.add((first + i) * stride), stride);
                    }
                }
            }
        };
        let tasks = strands.div_ceil(STRANDS_PER_TASK);
        match pool {
            Some(p) => p.install(|| (0..tasks).into_par_iter().for_each(task)),
            None => (0..tasks).for_each(task),
        }
    }
}
