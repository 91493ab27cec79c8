//! Copy-to-host output: the attributes the host asked for, interleaved per vertex, strand
//! after strand in the host's order. Only requested attributes are computed.

use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::lanes::Lane;
use glam::Vec3;

/// Strands below this count are written by one thread (splitting costs more than it saves).
const SERIAL_STRANDS: usize = 2048;

/// Writes every real point's attributes into `dst` (`points * stride` floats).
pub fn write_vertices(
    lay: &Layout,
    state: &[StateRow],
    wet: &[Lane],
    attrs: VertexAttributes,
    pool: Option<&super::pool::Pool>,
    dst: &mut [f32],
) {
    let mut job = || write_strands(lay, state, wet, attrs, 0..lay.strands, dst);
    match pool {
        Some(p) => p.install(job),
        None => job(),
    }
}

/// Writes host strands `range` into `dst`, which starts at the range's first vertex; halves
/// the range across threads with `rayon::join` (no allocation).
fn write_strands(
    lay: &Layout,
    state: &[StateRow],
    wet: &[Lane],
    attrs: VertexAttributes,
    range: std::ops::Range<usize>,
    dst: &mut [f32],
) {
    let stride = attrs.stride();
    if range.len() > SERIAL_STRANDS {
        let mid = range.start + range.len() / 2;
        let split = (lay.strand_first[mid] - lay.strand_first[range.start]) as usize * stride;
        let (lo, hi) = dst.split_at_mut(split);
        rayon::join(
            || write_strands(lay, state, wet, attrs, range.start..mid, lo),
            || write_strands(lay, state, wet, attrs, mid..range.end, hi),
        );
        return;
    }
    let pos_off = attrs.offset(VertexAttributes::POSITION);
    let tan_off = attrs.offset(VertexAttributes::TANGENT);
    let wet_off = attrs.offset(VertexAttributes::WETNESS);
    let base_vertex = lay.strand_first[range.start] as usize;
    for s in range {
        let (b, l) = lay.lane_of(s);
        let rows = &state[b * lay.rows..(b + 1) * lay.rows];
        let n = lay.strand_points(s);
        let v0 = lay.strand_first[s] as usize - base_vertex;
        for i in 0..n {
            let out = &mut dst[(v0 + i) * stride..(v0 + i + 1) * stride];
            if let Some(o) = pos_off {
                out[o..o + 3].copy_from_slice(&rows[i].x.get(l).to_array());
            }
            if let Some(o) = tan_off {
                let a = rows[i.saturating_sub(1)].x.get(l);
                let c = rows[(i + 1).min(n - 1)].x.get(l);
                out[o..o + 3].copy_from_slice(&(c - a).normalize_or(Vec3::Z).to_array());
            }
            if let Some(o) = wet_off {
                out[o] = if wet.is_empty() { 0.0 } else { wet[b * lay.rows + i][l] };
            }
        }
    }
}
