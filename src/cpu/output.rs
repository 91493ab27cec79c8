//! Copy-to-host output: the attributes the host asked for, interleaved per vertex, strand
//! after strand in the host's order. Only requested attributes are computed.

use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::lanes::{Lane, W};

/// Blocks below this count are written by one thread (splitting costs more than it saves).
const SERIAL_BLOCKS: usize = 256;

/// The host's vertex buffer, shared by the tasks that fill it: each writes only the vertices
/// of the strands in its blocks, and every strand lies in exactly one block.
struct Dst {
    ptr: *mut f32,
    len: usize,
}
// SAFETY: tasks write disjoint ranges (one per strand, each strand in one block); the buffer
// outlives them (they are joined before `write_vertices` returns).
unsafe impl Sync for Dst {}

/// Writes every real point's attributes into `dst` (`points * stride` floats).
pub fn write_vertices(
    lay: &Layout,
    state: &[StateRow],
    wet: &[Lane],
    attrs: VertexAttributes,
    pool: Option<&super::pool::Pool>,
    dst: &mut [f32],
) {
    assert_eq!(dst.len(), lay.mass.len() * attrs.stride(), "one vertex per point");
    let out = Dst {
        ptr: dst.as_mut_ptr(),
        len: dst.len(),
    };
    let job = || write_blocks(lay, state, wet, attrs, 0..lay.blocks, &out);
    match pool {
        Some(p) => p.install(job),
        None => job(),
    }
}

/// Writes the strands of `blocks`, block by block: a block's rows are read once while in cache
/// and each of its 8 strands is written to its place in the host's order (host order visits
/// blocks at random, which reads every block's rows 8 times from memory). Halves the range
/// across threads with `rayon::join` (no allocation).
fn write_blocks(
    lay: &Layout,
    state: &[StateRow],
    wet: &[Lane],
    attrs: VertexAttributes,
    blocks: std::ops::Range<usize>,
    dst: &Dst,
) {
    if blocks.len() > SERIAL_BLOCKS {
        let mid = blocks.start + blocks.len() / 2;
        rayon::join(
            || write_blocks(lay, state, wet, attrs, blocks.start..mid, dst),
            || write_blocks(lay, state, wet, attrs, mid..blocks.end, dst),
        );
        return;
    }
    let stride = attrs.stride();
    let pos_off = attrs.offset(VertexAttributes::POSITION);
    let tan_off = attrs.offset(VertexAttributes::TANGENT);
    let wet_off = attrs.offset(VertexAttributes::WETNESS);
    for b in blocks {
        let rows = &state[b * lay.rows..(b + 1) * lay.rows];
        // Each lane's strand: its first vertex's float offset and its point count (0: padding).
        let mut base = [0usize; W];
        let mut n = [0usize; W];
        for l in 0..W {
            let s = lay.strand_of_slot[b * W + l] as usize;
            if s < lay.strands {
                n[l] = lay.strand_points(s);
                base[l] = lay.strand_first[s] as usize * stride;
                assert!(base[l] + n[l] * stride <= dst.len);
            }
        }
        for (i, row) in rows.iter().enumerate() {
            // The 8 lanes' tangents at once (central difference, one-sided at the ends).
            let mut t = [[0.0f32; W]; 3];
            if tan_off.is_some() {
                let a = &rows[i.saturating_sub(1)].x;
                for l in 0..W {
                    let c = &rows[(i + 1).min(n[l].max(1) - 1)].x;
                    let (dx, dy, dz) = (c.x[l] - a.x[l], c.y[l] - a.y[l], c.z[l] - a.z[l]);
                    let len2 = dx * dx + dy * dy + dz * dz;
                    let inv = if len2 > 0.0 && len2.is_finite() {
                        1.0 / len2.sqrt()
                    } else {
                        0.0
                    };
                    // A zero-length difference points along +z, as `normalize_or(Vec3::Z)` does.
                    t[0][l] = dx * inv;
                    t[1][l] = dy * inv;
                    t[2][l] = if inv > 0.0 { dz * inv } else { 1.0 };
                }
            }
            for l in 0..W {
                if i >= n[l] {
                    continue;
                }
                // SAFETY: in bounds (the assert above: vertex i < n[l] of a range that fits);
                // strand l's vertices are written by this task only.
                unsafe {
                    let v = dst.ptr.add(base[l] + i * stride);
                    if let Some(o) = pos_off {
                        *v.add(o) = row.x.x[l];
                        *v.add(o + 1) = row.x.y[l];
                        *v.add(o + 2) = row.x.z[l];
                    }
                    if let Some(o) = tan_off {
                        *v.add(o) = t[0][l];
                        *v.add(o + 1) = t[1][l];
                        *v.add(o + 2) = t[2][l];
                    }
                    if let Some(o) = wet_off {
                        *v.add(o) = if wet.is_empty() { 0.0 } else { wet[b * lay.rows + i][l] };
                    }
                }
            }
        }
    }
}
