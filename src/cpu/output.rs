//! Copy-to-host output: the attributes the host asked for, interleaved per vertex, strand
//! after strand in the host's order. Only requested attributes are computed.

use super::layout::{Layout, StateRow};
use crate::params::VertexAttributes;
use crate::physics::lanes::{Lane, L3, W};

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

/// What every task needs: the layout, the state, the attribute offsets and the target.
struct Job<'a> {
    lay: &'a Layout,
    state: &'a [StateRow],
    wet: &'a [Lane],
    /// The positions the output blends from, per row, and how far toward the state.
    blend: Option<(&'a [L3], f32)>,
    stride: usize,
    pos: Option<usize>,
    tan: Option<usize>,
    wetness: Option<usize>,
    avx2: bool,
    dst: Dst,
}

/// Writes every real point's attributes into `dst` (`points * stride` floats). With `blend`
/// = (`from`, `a`), the positions (and the tangents made from them) are `from` moved toward
/// the state's by `a` ([`L3::toward`]).
#[allow(clippy::too_many_arguments)]
pub fn write_vertices(
    lay: &Layout,
    state: &[StateRow],
    wet: &[Lane],
    blend: Option<(&[L3], f32)>,
    attrs: VertexAttributes,
    pool: Option<&super::pool::Pool>,
    avx2: bool,
    dst: &mut [f32],
) {
    assert_eq!(dst.len(), lay.mass.len() * attrs.stride(), "one vertex per point");
    let job = Job {
        lay,
        state,
        wet,
        blend,
        stride: attrs.stride(),
        pos: attrs.offset(VertexAttributes::POSITION),
        tan: attrs.offset(VertexAttributes::TANGENT),
        wetness: attrs.offset(VertexAttributes::WETNESS),
        avx2,
        dst: Dst {
            ptr: dst.as_mut_ptr(),
            len: dst.len(),
        },
    };
    match pool {
        Some(p) => p.install(|| write_range(&job, 0..lay.blocks)),
        // One thread: no split (a `rayon::join` outside a pool would run on rayon's global
        // threads, away from the caches the step just filled).
        None => write_blocks_best(&job, 0..lay.blocks),
    }
}

/// Halves the block range across threads with `rayon::join` (no allocation) down to
/// `SERIAL_BLOCKS`, then writes each block.
fn write_range(job: &Job, blocks: std::ops::Range<usize>) {
    if blocks.len() > SERIAL_BLOCKS {
        let mid = blocks.start + blocks.len() / 2;
        rayon::join(
            || write_range(job, blocks.start..mid),
            || write_range(job, mid..blocks.end),
        );
        return;
    }
    write_blocks_best(job, blocks)
}

super::avx2::avx2_or_base!(
    /// [`write_blocks`] compiled for AVX2 where the CPU has it.
    fn write_blocks_best(job: &Job, blocks: std::ops::Range<usize>) => write_blocks
);

/// Rows staged per pass over a block: the stage is 8 lanes x (`STAGE_ROWS` x 7 + 8) floats,
/// 3.8 KB, which stays in L1.
const STAGE_ROWS: usize = 16;
/// Floats per lane of the stage: `STAGE_ROWS` vertices of at most 7 floats, plus room for the
/// last 8-float store.
pub(super) const STAGE: usize = STAGE_ROWS * 7 + 8;

/// Writes the strands of `blocks`, block by block: a block's rows are read once while in
/// cache, each row's 8 tangents are computed at once, the row's 8 vertices are laid out in a
/// small stage (one contiguous run per strand), and each strand's run is copied to its place in
/// the host's order in one piece. Writing the host's buffer vertex by vertex, 8 strands at a
/// time, cost 2-3x more: each float was a store to a line in another strand's place.
#[inline(always)]
fn write_blocks(job: &Job, blocks: std::ops::Range<usize>) {
    let lay = job.lay;
    let stride = job.stride;
    let mut stage = [[0.0f32; STAGE]; W];
    // A blended output's rows, block by block (allocated once per task, and only when blending).
    let mut mixed: Vec<StateRow> = Vec::new();
    let end = blocks.end;
    for b in blocks {
        if b + PREFETCH_AHEAD < end {
            prefetch_block(job, b + PREFETCH_AHEAD);
        }
        let here = b * lay.rows..(b + 1) * lay.rows;
        let rows = match job.blend {
            None => &job.state[here],
            Some((from, a)) => {
                mixed.clear();
                mixed.extend(job.state[here.clone()].iter().zip(&from[here]).map(|(r, p)| StateRow {
                    x: p.toward(&r.x, a),
                    v: r.v,
                }));
                &mixed[..]
            }
        };
        // Each lane's strand: its first vertex's float offset and its point count (0: padding).
        let mut base = [0usize; W];
        let mut n = [0usize; W];
        for l in 0..W {
            let s = lay.strand_of_slot[b * W + l] as usize;
            if s < lay.strands {
                n[l] = lay.strand_points(s);
                base[l] = lay.strand_first[s] as usize * stride;
                assert!(base[l] + n[l] * stride <= job.dst.len);
            }
        }
        let n32 = n.map(|c| c as u32);
        let used = n.iter().copied().max().unwrap_or(0);
        for r0 in (0..used).step_by(STAGE_ROWS) {
            let r1 = (r0 + STAGE_ROWS).min(used);
            for i in r0..r1 {
                let row = &rows[i];
                let t = if job.tan.is_some() {
                    tangents(rows, i, &n32)
                } else {
                    L3::ZERO
                };
                // The components in the host's order (the rest of the 8 are not copied out).
                let mut cols = [[0.0f32; W]; 8];
                if let Some(o) = job.pos {
                    cols[o..o + 3].copy_from_slice(&[row.x.x, row.x.y, row.x.z]);
                }
                if let Some(o) = job.tan {
                    cols[o..o + 3].copy_from_slice(&[t.x, t.y, t.z]);
                }
                if let (Some(o), false) = (job.wetness, job.wet.is_empty()) {
                    cols[o] = job.wet[b * lay.rows + i];
                }
                stage_row(job.avx2, &cols, &mut stage, (i - r0) * stride, stride);
            }
            for l in 0..W {
                let end = r1.min(n[l]);
                if end <= r0 {
                    continue;
                }
                let len = (end - r0) * stride;
                // SAFETY: `base[l] + end * stride <= dst.len` (the assert above, end <= n[l]);
                // strand l's vertices are written by this task only.
                unsafe { copy_run(&stage[l][..len], job.dst.ptr.add(base[l] + r0 * stride)) };
            }
        }
    }
}

/// How many blocks ahead the destination lines are requested.
const PREFETCH_AHEAD: usize = 4;

/// Asks the cache for the destination lines of block `b`'s strands, for writing, so the copies
/// that come later find them: a block's 8 strands sit at unrelated places in the host's
/// buffer, which the hardware prefetcher cannot predict.
#[inline(always)]
fn prefetch_block(job: &Job, b: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_ET0};
        let lay = job.lay;
        for l in 0..W {
            let s = lay.strand_of_slot[b * W + l] as usize;
            if s >= lay.strands {
                continue;
            }
            let first = lay.strand_first[s] as usize * job.stride;
            let last = lay.strand_first[s + 1] as usize * job.stride;
            // Every 64-byte line of the run: one request per 16 floats, and the last float.
            let mut f = first;
            while f < last {
                // SAFETY: a prefetch never faults, and the address lies inside `dst`.
                unsafe { _mm_prefetch::<_MM_HINT_ET0>(job.dst.ptr.add(f) as *const i8) };
                f += 16;
            }
            // SAFETY: as above.
            unsafe { _mm_prefetch::<_MM_HINT_ET0>(job.dst.ptr.add(last - 1) as *const i8) };
        }
    }
}

/// Copies `src` to `dst` in 8-float pieces, the last one ending exactly at the run's end
/// (overlapping the one before): a strand's run is a few dozen floats, where a `memcpy` call
/// costs as much as the copy.
///
/// # Safety
/// `dst .. dst + src.len()` must be writable and not overlap `src`.
#[inline(always)]
pub(super) unsafe fn copy_run(src: &[f32], dst: *mut f32) {
    let len = src.len();
    if len < 8 {
        std::ptr::copy_nonoverlapping(src.as_ptr(), dst, len);
        return;
    }
    let piece = |at: usize| {
        let v = std::ptr::read_unaligned(src.as_ptr().add(at) as *const [f32; 8]);
        std::ptr::write_unaligned(dst.add(at) as *mut [f32; 8], v);
    };
    let mut at = 0;
    while at + 8 < len {
        piece(at);
        at += 8;
    }
    piece(len - 8);
}

/// Lays lane `l`'s vertex out at `stage[l][at..at + stride]` for every lane: an 8 x 8 register
/// transpose on AVX2 (it also writes up to 8 - `stride` floats past the vertex, which the
/// next row overwrites or nobody copies), a float at a time elsewhere.
#[inline(always)]
fn stage_row(avx2: bool, cols: &[Lane; 8], stage: &mut [[f32; STAGE]; W], at: usize, stride: usize) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: AVX2 is present (`avx2` comes from `cpu_has_avx2`).
        unsafe { super::transpose::transpose_into(cols, stage, at) };
        return;
    }
    let _ = avx2;
    for (l, lane) in stage.iter_mut().enumerate() {
        for (k, col) in cols[..stride].iter().enumerate() {
            lane[at + k] = col[l];
        }
    }
}

/// The unit tangents of row `i`'s 8 points: the central difference of the neighbours, one-sided
/// at a strand's ends (lane `l` ends at row `n[l] - 1`); a zero or non-finite difference gives
/// +z, as `normalize_or(Vec3::Z)` does. Every lane takes the same path: selects are bit masks
/// and the tests are non-short-circuit `&`, so the compiler keeps all 8 lanes in one vector
/// (a `&&` or a chosen pointer per lane turns this into 8 scalar branches, 4x the work).
#[inline(always)]
fn tangents(rows: &[StateRow], i: usize, n: &[u32; W]) -> L3 {
    let a = &rows[i.saturating_sub(1)].x;
    let here = &rows[i].x;
    let next = &rows[(i + 1).min(rows.len() - 1)].x;
    let mut t = L3::ZERO;
    for l in 0..W {
        // All ones where this lane's strand has a next point (take it), else zero (take this).
        let keep = 0u32.wrapping_sub(((i as u32) + 1 < n[l]) as u32);
        let pick = |nv: f32, hv: f32| f32::from_bits((nv.to_bits() & keep) | (hv.to_bits() & !keep));
        let cx = pick(next.x[l], here.x[l]);
        let cy = pick(next.y[l], here.y[l]);
        let cz = pick(next.z[l], here.z[l]);
        t.x[l] = cx - a.x[l];
        t.y[l] = cy - a.y[l];
        t.z[l] = cz - a.z[l];
    }
    unit_lanes(&t)
}

/// Each lane of `d` over its length, or +z where that is zero or not finite (as
/// `normalize_or(Vec3::Z)` and the follower law's `tangent` give), branch-free.
#[inline(always)]
pub(super) fn unit_lanes(d: &L3) -> L3 {
    let mut t = L3::ZERO;
    for l in 0..W {
        let (dx, dy, dz) = (d.x[l], d.y[l], d.z[l]);
        let len2 = dx * dx + dy * dy + dz * dz;
        // All ones where the length is usable; the selects are bit masks (no branch per lane).
        let ok = 0u32.wrapping_sub(((len2 > 0.0) & (len2 < f32::INFINITY)) as u32);
        let one = 1.0f32.to_bits() & !ok;
        let inv = 1.0 / f32::from_bits((len2.to_bits() & ok) | one).sqrt();
        t.x[l] = f32::from_bits((dx * inv).to_bits() & ok);
        t.y[l] = f32::from_bits((dy * inv).to_bits() & ok);
        t.z[l] = f32::from_bits((dz * inv).to_bits() & ok | one);
    }
    t
}

/// Lays the 8 vertices whose components are `cols` out one after the other at
/// `run[at..at + 8 * stride]`: an 8 x 8 register transpose on AVX2 (which also writes up to
/// 8 - `stride` floats past the eighth), a float at a time elsewhere.
#[inline(always)]
pub(super) fn stage_run(avx2: bool, cols: &[Lane; 8], run: &mut [f32], at: usize, stride: usize) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: AVX2 is present (`avx2` comes from `cpu_has_avx2`).
        unsafe { super::transpose::transpose_run(cols, run, at, stride) };
        return;
    }
    let _ = avx2;
    for l in 0..W {
        for (k, col) in cols[..stride].iter().enumerate() {
            run[at + l * stride + k] = col[l];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 writer and the portable one write the same bits, for every attribute set, on
    /// ragged strands with random positions and wetness (tests/output.rs checks the result
    /// against its definition through the public API).
    #[test]
    fn avx2_and_portable_writers_agree() {
        assert!(
            !cfg!(target_arch = "x86_64") || super::super::avx2::cpu_has_avx2(),
            "this test compares the AVX2 writer; the machine has no AVX2"
        );
        let counts: Vec<u32> = (0..21).map(|s| 2 + (s * 11) % 37).collect();
        let (_, lay, state, wet) = super::super::layout::fixture::ragged(&counts, 11, (1.0, 0.0));
        for bits in 1..=7 {
            let attrs = VertexAttributes(bits);
            let n = lay.mass.len() * attrs.stride();
            let (mut a, mut b) = (vec![0.0f32; n], vec![1.0f32; n]);
            write_vertices(&lay, &state, &wet, None, attrs, None, false, &mut a);
            write_vertices(&lay, &state, &wet, None, attrs, None, true, &mut b);
            let same = a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
            assert!(same, "attributes {bits}: the two writers differ");
        }
    }
}
