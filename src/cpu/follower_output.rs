//! Pass write_followers: every host strand from the guide points gathered by pass
//! `guide_frames` (`followers.rs`), eight points at a time ([`follow_lanes`]) where the
//! strand's guides have its point count, else point by point ([`output_point`]); the same bits
//! either way (the tests hold them equal). With skinned roots each strand is then moved onto
//! its own root ([`root_strand`]). Then the vertices, eight at a time: tangents as
//! lanes, laid out by a register transpose in a stage in L1, copied to the host's buffer in
//! one piece.

use super::followers::{for_tasks, Shared, STRANDS_PER_TASK};
use super::guide_columns::{GuideColumns, FLOATS_PER_LINE};
use super::output::{copy_run, stage_run, unit_lanes};
use crate::groom::MAX_POINTS_PER_STRAND;
use crate::params::VertexAttributes;
use crate::physics::follow::output_point;
use crate::physics::follow_lanes::{blend_lanes, follow_lanes};
use crate::physics::follow_roots::{root_strand, OwnRoot, StrandPositions};
use crate::physics::followers::{Follow, Followers};
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::roots::RootFrame;
use glam::Vec3;

/// Pass write_followers: every host strand of `fl` from the guide points `points`, the output
/// blended from the old bindings by `blend`, on its own root frame `roots[h]` with skinned
/// roots (`roots` empty without), in the host's order (its rest pose, bindings and
/// vertices are read and written in memory order; a groom's neighbouring strands are near each
/// other in it, so they read the same guides from cache), each strand's vertices written once,
/// in place.
pub(super) fn write_followers(
    fl: &Followers,
    points: &GuideColumns,
    blend: f32,
    roots: &[RootFrame],
    attrs: VertexAttributes,
    pool: Option<&super::pool::Pool>,
    dst: &mut [f32],
) {
    let job = Job::new(fl, points, blend, roots, attrs, dst, super::avx2::cpu_has_avx2());
    run_job(&job, fl.strand_first.len() - 1, pool);
}

impl<'a> Job<'a> {
    /// Writing `fl`'s strands' `attrs` into `dst` from `points`, blended by `blend`, on
    /// `roots`.
    fn new(
        fl: &'a Followers,
        points: &'a GuideColumns,
        blend: f32,
        roots: &'a [RootFrame],
        attrs: VertexAttributes,
        dst: &mut [f32],
        avx2: bool,
    ) -> Self {
        Job {
            fl,
            points,
            blend,
            roots,
            one_point: false,
            stride: attrs.stride(),
            pos: attrs.offset(VertexAttributes::POSITION),
            tan: attrs.offset(VertexAttributes::TANGENT),
            wetness: attrs.offset(VertexAttributes::WETNESS),
            dst: Shared(dst.as_mut_ptr()),
            dst_len: dst.len(),
            avx2,
        }
    }
}

/// Writes host strands `0..strands` as `job` says, split across the pool.
fn run_job(job: &Job, strands: usize, pool: Option<&super::pool::Pool>) {
    let task = |t: usize| write_strands_best(job, t * STRANDS_PER_TASK..((t + 1) * STRANDS_PER_TASK).min(strands));
    for_tasks(pool, strands.div_ceil(STRANDS_PER_TASK), task);
}

/// What pass write_followers reads and where it writes.
struct Job<'a> {
    fl: &'a Followers,
    points: &'a GuideColumns,
    blend: f32,
    /// Each host strand's root frame (skinned roots; else empty).
    roots: &'a [RootFrame],
    /// The one-point law for every strand (the tests' reference for the lanes).
    one_point: bool,
    stride: usize,
    pos: Option<usize>,
    tan: Option<usize>,
    wetness: Option<usize>,
    dst: Shared<f32>,
    dst_len: usize,
    avx2: bool,
}

super::avx2::avx2_or_base!(
    /// [`write_strands`] compiled for AVX2 where the machine has it.
    fn write_strands_best(job: &Job, strands: std::ops::Range<usize>) => write_strands
);

/// Host strands `strands`: each strand's points (eight at a time where its guides allow, see
/// [`point_for_point`]), then its vertices eight at a time: tangents as lanes, laid out in a
/// stage in L1, copied to the host's buffer in one piece.
#[inline(always)]
fn write_strands(job: &Job, strands: std::ops::Range<usize>) {
    let fl = job.fl;
    let stride = job.stride;
    let mut pts = StrandPoints::new();
    let mut stage = vec![0.0f32; (MAX_POINTS_PER_STRAND + W) * 7 + 8];
    let end = strands.end;
    for h in strands {
        if h + GUIDES_AHEAD < end {
            prefetch_guides(job, h + GUIDES_AHEAD);
        }
        let first = fl.strand_first[h] as usize;
        let n = fl.strand_first[h + 1] as usize - first;
        let blending = job.blend < 1.0 && !fl.from.is_empty();
        let lanes = !job.one_point
            && point_for_point(fl, &fl.follow[h], n)
            && (!blending || point_for_point(fl, &fl.from[h], n));
        if lanes {
            follow_strand_lanes(job, h, first, n, blending, &mut pts);
        } else {
            let at = |p: u32| job.points.point(p as usize);
            for i in 0..n {
                let (x, w) = output_point(fl, h, i as u32, job.blend, &at);
                pts.set(i, x, w);
            }
        }
        if !job.roots.is_empty() {
            let own = OwnRoot {
                frame: job.roots[h],
                rest_root: fl.rest[first],
                points: fl.root_points[h],
            };
            root_strand(&own, n as u32, |i| fl.rest[first + i as usize], &mut pts);
        }
        pts.close(n);
        for i0 in (0..n).step_by(W) {
            let mut cols = [[0.0f32; W]; 8];
            if let Some(o) = job.pos {
                let x = pts.lanes(i0 + 1);
                cols[o..o + 3].copy_from_slice(&[x.x, x.y, x.z]);
            }
            if let Some(o) = job.tan {
                let (a, b) = (pts.lanes(i0), pts.lanes(i0 + 2));
                let d = L3 {
                    x: std::array::from_fn(|l| b.x[l] - a.x[l]),
                    y: std::array::from_fn(|l| b.y[l] - a.y[l]),
                    z: std::array::from_fn(|l| b.z[l] - a.z[l]),
                };
                let t = unit_lanes(&d);
                cols[o..o + 3].copy_from_slice(&[t.x, t.y, t.z]);
            }
            if let Some(o) = job.wetness {
                cols[o].copy_from_slice(&pts.w[i0 + 1..i0 + 1 + W]);
            }
            stage_run(job.avx2, &cols, &mut stage, i0 * stride, stride);
        }
        assert!((first + n) * stride <= job.dst_len);
        // SAFETY: strand `h`'s vertices lie inside `dst` (asserted), only this task writes
        // them, and the stage is not the destination.
        unsafe { copy_run(&stage[..n * stride], job.dst.0.add(first * stride)) };
    }
}

/// How many host strands ahead the guides' columns and rest pose are requested.
const GUIDES_AHEAD: usize = 4;

/// Asks the cache for what host strand `h` will read: its guides' columns (every line of
/// each guide's block) and its rest points. Neighbouring host strands follow guides at
/// unrelated places in the columns (the host's order is its own), so each strand's reads
/// missed the cache one after another: a third of the pass at a quarter of the strands
/// simulated.
#[inline(always)]
fn prefetch_guides(job: &Job, h: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let (fl, data) = (job.fl, job.points.data());
        let f = &fl.follow[h];
        for k in 0..3 {
            if k > 0 && f.weights[k] == 0.0 {
                continue;
            }
            let g = f.guides[k] as usize;
            let (base, len) = (job.points.base[g], GuideColumns::PLANES * job.points.width[g]);
            for line in (base..(base + len).min(data.len())).step_by(FLOATS_PER_LINE) {
                // SAFETY: a prefetch never faults, and the address lies inside the columns.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(data.as_ptr().add(line) as *const i8) };
            }
        }
        let (first, last) = (fl.strand_first[h] as usize, fl.strand_first[h + 1] as usize);
        for p in (first..last).step_by(FLOATS_PER_LINE / 3) {
            // SAFETY: as above; the address lies inside the rest pose.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(fl.rest.as_ptr().add(p) as *const i8) };
        }
    }
}

/// One strand's output points as columns, point `i` at `i + 1`, with its ends repeated at 0
/// and `n + 1` ([`StrandPoints::close`]), so a tangent's neighbours (one-sided at the ends)
/// are plain loads: `i` and `i + 2`.
struct StrandPoints {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    w: Vec<f32>,
}

impl StrandPoints {
    /// Room for the longest strand, a lane group's overrun and the two ends.
    fn new() -> Self {
        let len = MAX_POINTS_PER_STRAND + 2 * W;
        StrandPoints {
            x: vec![0.0; len],
            y: vec![0.0; len],
            z: vec![0.0; len],
            w: vec![0.0; len],
        }
    }

    /// Point `i`.
    #[inline(always)]
    fn set(&mut self, i: usize, x: Vec3, w: f32) {
        (self.x[i + 1], self.y[i + 1], self.z[i + 1], self.w[i + 1]) = (x.x, x.y, x.z, w);
    }

    /// Points `i0 .. i0 + W` from lanes.
    #[inline(always)]
    fn set_lanes(&mut self, i0: usize, x: &L3, w: &Lane) {
        let at = i0 + 1..i0 + 1 + W;
        self.x[at.clone()].copy_from_slice(&x.x);
        self.y[at.clone()].copy_from_slice(&x.y);
        self.z[at.clone()].copy_from_slice(&x.z);
        self.w[at].copy_from_slice(w);
    }

    /// Repeats the first and last of `n` points past the ends.
    #[inline(always)]
    fn close(&mut self, n: usize) {
        for c in [&mut self.x, &mut self.y, &mut self.z] {
            c[0] = c[1];
            c[n + 1] = c[n];
        }
    }

    /// Positions at columns `k .. k + W`.
    #[inline(always)]
    fn lanes(&self, k: usize) -> L3 {
        let lane = |c: &[f32]| -> Lane {
            let mut v = [0.0; W];
            v.copy_from_slice(&c[k..k + W]);
            v
        };
        L3 {
            x: lane(&self.x),
            y: lane(&self.y),
            z: lane(&self.z),
        }
    }
}

impl StrandPositions for StrandPoints {
    #[inline(always)]
    fn get(&self, i: u32) -> Vec3 {
        let i = i as usize + 1;
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    fn set(&mut self, i: u32, x: Vec3) {
        let i = i as usize + 1;
        (self.x[i], self.y[i], self.z[i]) = (x.x, x.y, x.z);
    }
}

/// Whether every guide `f` reads has `n` points (then a follower's point `i` is each guide's
/// point `i`, and [`follow_lanes`] applies).
#[inline(always)]
fn point_for_point(fl: &Followers, f: &Follow, n: usize) -> bool {
    (0..3).all(|k| (k > 0 && f.weights[k] == 0.0) || fl.spans[f.guides[k] as usize].count as usize == n)
}

/// Host strand `h`'s `n` points (first host point `first`) into `pts`, eight at a time.
#[inline(always)]
fn follow_strand_lanes(job: &Job, h: usize, first: usize, n: usize, blending: bool, pts: &mut StrandPoints) {
    let fl = job.fl;
    for i0 in (0..n).step_by(W) {
        let mut rest = L3::ZERO;
        for l in 0..W {
            rest.set(l, fl.rest[first + (i0 + l).min(n - 1)]);
        }
        let mut out = follow_lanes_at(job, &fl.follow[h], i0, &rest);
        if blending {
            let old = follow_lanes_at(job, &fl.from[h], i0, &rest);
            out = blend_lanes(&old, &out, job.blend);
        }
        pts.set_lanes(i0, &out.0, &out.1);
    }
}

/// [`follow_lanes`] for points `i0 .. i0 + W` of a follower with rest positions `rest`.
#[inline(always)]
fn follow_lanes_at(job: &Job, f: &Follow, i0: usize, rest: &L3) -> (L3, Lane) {
    // A slot with no weight is not read; it repeats slot 0's lanes.
    let at = |k: usize| f.guides[if f.weights[k] == 0.0 { 0 } else { k }] as usize;
    let g0 = job.points.lanes(at(0), i0);
    let g1 = job.points.lanes(at(1), i0);
    let g2 = job.points.lanes(at(2), i0);
    follow_lanes(f, [&g0, &g1, &g2], rest, job.fl.clump)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::followers::GuideSpan;
    use crate::scenes::Lcg;

    /// The lanes and the one-point law write the same bits, with AVX2 and without, for every
    /// attribute set, blending or not: strands of 3 to 21 points (some longer than a lane
    /// group, some not a multiple of it) bound to three guides of their own length, or (every
    /// fourth strand) to guides of other lengths, which takes the one-point law.
    #[test]
    fn lanes_write_the_one_point_laws_bits() {
        let mut rng = Lcg(3);
        let mut r = || rng.next_f32() * 2.0 - 1.0;
        let lengths = [3u32, 8, 11, 16, 21];
        let spans: Vec<GuideSpan> = (0..10u32)
            .map(|g| GuideSpan {
                first: (0..g).map(|k| lengths[k as usize % 5]).sum(),
                rest: 0,
                count: lengths[g as usize % 5],
                host: g,
            })
            .collect();
        let total = spans.last().map_or(0, |s| s.first + s.count) as usize;
        let mut points = GuideColumns::default();
        points.resize(&spans);
        for (g, s) in spans.iter().enumerate() {
            for j in 0..s.count as usize {
                for c in 0..GuideColumns::PLANES {
                    let v = if c == 3 { r().abs() } else { r() };
                    let k = points.base[g] + c * points.width[g] + j;
                    bytemuck::cast_slice_mut::<_, f32>(&mut points.lines)[k] = v;
                }
            }
        }
        assert_eq!(points.guide_of.len(), total);
        let mut strand_first = vec![0u32];
        let (mut follow, mut from) = (Vec::new(), Vec::new());
        for h in 0..40usize {
            let len_slot = h % 5;
            let n = lengths[len_slot];
            strand_first.push(strand_first[h] + n);
            // Guides of the strand's own length: slots len_slot, len_slot + 5.
            let own = [len_slot as u32, len_slot as u32 + 5, len_slot as u32];
            let guides = if h % 4 == 3 {
                [(len_slot as u32 + 1) % 10, own[0], own[1]]
            } else {
                own
            };
            let (a, b) = (r().abs(), r().abs());
            let weights = match h % 3 {
                0 => [1.0, 0.0, 0.0],
                1 => [a / (a + b), b / (a + b), 0.0],
                _ => [a / 2.0, b / 2.0, 1.0 - a / 2.0 - b / 2.0],
            };
            follow.push(Follow { guides, weights });
            from.push(Follow {
                guides: [own[1], own[0], own[0]],
                weights: [0.5, 0.5, 0.0],
            });
        }
        let rest: Vec<Vec3> = (0..strand_first[40]).map(|_| Vec3::new(r(), r(), r())).collect();
        let mut fl = Followers {
            strand_first,
            rest,
            spans,
            follow,
            from,
            clump: 0.7,
            root_points: Vec::new(),
        };
        // Skinned roots: each strand on a frame of its own, 0, 1 or 2 root points.
        let frames: Vec<RootFrame> = (0..40)
            .map(|_| RootFrame {
                position: Vec3::new(r(), r(), r()),
                rotation: glam::Quat::from_rotation_y(r() * 3.0),
            })
            .collect();
        let root_points: Vec<u32> = (0..40).map(|h| h % 3).collect();
        // Blends first: the settled case clears the old bindings.
        for (blend, roots) in [(0.3f32, false), (0.3, true), (1.0, false)] {
            if blend == 1.0 {
                fl.from.clear();
            }
            let roots: &[RootFrame] = if roots { &frames } else { &[] };
            fl.root_points = if roots.is_empty() {
                Vec::new()
            } else {
                root_points.clone()
            };
            for bits in 1..=7 {
                let attrs = VertexAttributes(bits);
                let write = |one_point: bool, avx2: bool| {
                    let mut dst = vec![f32::NAN; fl.rest.len() * attrs.stride()];
                    let job = Job {
                        one_point,
                        ..Job::new(&fl, &points, blend, roots, attrs, &mut dst, avx2)
                    };
                    run_job(&job, fl.follow.len(), None);
                    dst
                };
                let want = write(true, false);
                assert!(want.iter().all(|v| v.is_finite()), "every vertex written");
                let avx2 = super::super::avx2::cpu_has_avx2();
                for (one_point, avx2) in [(false, false), (false, avx2), (true, avx2)] {
                    let got = write(one_point, avx2);
                    let same = got.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits());
                    assert!(
                        same,
                        "blend {blend}, roots {}, attributes {bits}, one point {one_point}, avx2 {avx2}",
                        roots.len()
                    );
                }
            }
        }
    }
}
