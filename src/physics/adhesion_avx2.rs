//! Eq. 2's gather ([`super::adhesion::gather_run_lanes`]) written in AVX2 intrinsics, for the
//! CPU kernel's AVX2 build. Same operations in the same order, no fused multiply-add: the
//! same bits as the lane form (the tests below hold it to them).
//!
//! Why intrinsics: the lane form's test "is any lane within `r_max` of this particle" is a
//! branch on a reduction across lanes, and LLVM kept that part, the hot one (three candidate
//! particles in four are rejected there), scalar: eight subtracts, multiplies and compares one
//! lane at a time. On the paper scene with 1,000 particles (a frozen frame 30, one thread)
//! the pass went from 2.7 ms to 1.2 ms a substep written this way. It then tests a row's
//! candidates first and pulls the listed ones after (the same pulls in the same order): the
//! paper scene with 1,000 particles 2.31 -> 2.22 ms a frame on 2 threads. Where the stability
//! limit counts a row, its count computes each listed pair's distance, parabola and stiffness
//! and the pulls take them from it (`Terms`) instead of computing them again: 6-15 % of the
//! paper scene's frame with 1,000 drops, 2-5 % left (docs/PERFORMANCE.md, 2026-12-01).

use super::absorb::WetRow;
use super::adhesion::{Reaction, Strength, MIN_DISTANCE};
use super::lanes::{Lane, L3, W};
use super::pull_limit::PullLimit;
use std::arch::x86_64::*;

/// The most particles within reach a row lists before it pulls them (the list is on the stack).
const HIT_BATCH: usize = 32;

/// What a pair's pull and its stiffness share, per lane: the distance, eq. 2's parabola and
/// [`super::adhesion::pair_stiffness`] before its reach is applied.
#[derive(Clone, Copy)]
struct Terms {
    d: __m256,
    shell: __m256,
    stiff: __m256,
}

/// The sums of the lanes of `a`, `b`, `c` and `d` in [`super::lanes::hsum`]'s order (halves
/// first, then pairs: (0 + 2) + (1 + 3)), as the lanes of one vector: the same additions in
/// the same order, so the same bits, with one transpose of four half-sums instead of four
/// reductions.
#[target_feature(enable = "avx2")]
#[inline]
fn hsum4(a: __m256, b: __m256, c: __m256, d: __m256) -> __m128 {
    let half = |v: __m256| _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
    let (a, b, c, d) = (half(a), half(b), half(c), half(d));
    let (ab01, cd01) = (_mm_unpacklo_ps(a, b), _mm_unpacklo_ps(c, d));
    let (ab23, cd23) = (_mm_unpackhi_ps(a, b), _mm_unpackhi_ps(c, d));
    let (e0, e1) = (_mm_movelh_ps(ab01, cd01), _mm_movehl_ps(cd01, ab01));
    let (e2, e3) = (_mm_movelh_ps(ab23, cd23), _mm_movehl_ps(cd23, ab23));
    _mm_add_ps(_mm_add_ps(e0, e2), _mm_add_ps(e1, e3))
}

/// From a row's lanes (`hx`, `hy`, `hz`) to particle `slot` of `sorted`: the offset and its
/// squared length, computed alike by the gather's test and its pull.
#[target_feature(enable = "avx2")]
#[inline]
fn offset_to(sorted: [&[f32]; 3], slot: u32, hx: __m256, hy: __m256, hz: __m256) -> ((__m256, __m256, __m256), __m256) {
    let k = slot as usize;
    let dx = _mm256_sub_ps(_mm256_set1_ps(sorted[0][k]), hx);
    let dy = _mm256_sub_ps(_mm256_set1_ps(sorted[1][k]), hy);
    let dz = _mm256_sub_ps(_mm256_set1_ps(sorted[2][k]), hz);
    let d2 = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
        _mm256_mul_ps(dz, dz),
    );
    ((dx, dy, dz), d2)
}

/// [`super::adhesion::gather_row_lanes`] on AVX2: the same arguments, effects and bits. One
/// call per row: called per run, the kernel did not inline it and paid a call per run. The
/// stability limit's sums come from the first list of particles within reach when it holds
/// all of them, keeping each pair's `Terms` for its pull (a row with more counts them first,
/// as the lane form does).
///
/// # Safety
/// The CPU must support AVX2 (callers check `is_x86_feature_detected!("avx2")` once).
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
pub unsafe fn gather_row_lanes(
    x: &L3,
    mask: &Lane,
    weight: &Lane,
    bundle: Option<&Lane>,
    inv_mass: &Lane,
    limit: &PullLimit,
    runs: &[(u32, u32)],
    sorted: [&[f32]; 3],
    reactions: &mut Vec<Reaction>,
    acc: &mut L3,
    near: &mut Lane,
    r_min: f32,
    r_max: f32,
    s: Strength,
    mut wet: Option<&mut WetRow>,
) {
    let load = |a: &Lane| -> __m256 {
        // SAFETY: a `Lane` is W = 8 contiguous f32; unaligned loads take any address.
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    };
    let (hx, hy, hz, m) = (load(&x.x), load(&x.y), load(&x.z), load(mask));
    // The lanes' weights, limited once the first list is made.
    let mut share = load(weight);
    let mut limited = false;
    let (mut ax, mut ay, mut az) = (load(&acc.x), load(&acc.y), load(&acc.z));
    let mut marks = load(near);
    // A guide groom's bundles: what the particle's reaction and stiffness are scaled by.
    let bundle = bundle.map(load);
    let zero = _mm256_setzero_ps();
    let r2 = _mm256_set1_ps(r_max * r_max);
    let min2 = _mm256_set1_ps(MIN_DISTANCE * MIN_DISTANCE);
    let (two, one) = (_mm256_set1_ps(2.0), _mm256_set1_ps(1.0));
    let quarter = _mm256_set1_ps(0.25 * (r_max - r_min));
    let (rmin, rmax, width) = (
        _mm256_set1_ps(r_min),
        _mm256_set1_ps(r_max),
        _mm256_set1_ps(r_min - r_max),
    );
    // Two phases: the candidates' reach test with the particles that pass listed without a
    // branch, then the pulls of the listed ones. Tested and pulled in one loop, a branch on
    // each candidate's test (about half pass) went each way at random; listed first, the
    // pulls' long chains (square root, two divisions, three lane sums) also overlap.
    let mut hits = [0u32; HIT_BATCH];
    // Each listed particle's distance, profile and pair stiffness per lane, when the
    // stability limit's count computed them (written before they are read: no zeroing).
    let mut terms = [std::mem::MaybeUninit::<Terms>::uninit(); HIT_BATCH];
    let shell_terms = |d2: __m256| -> Terms {
        let d = _mm256_sqrt_ps(d2);
        let u = _mm256_div_ps(_mm256_sub_ps(_mm256_sub_ps(_mm256_mul_ps(two, d), rmin), rmax), width);
        let shell = _mm256_sub_ps(one, _mm256_mul_ps(u, u));
        // `adhesion::pair_stiffness`: the larger of u and (r_max - r_min) g / 4d, the latter
        // at most 1.
        let across = _mm256_min_ps(_mm256_div_ps(_mm256_mul_ps(quarter, shell), d), one);
        Terms {
            d,
            shell,
            stiff: _mm256_max_ps(u, across),
        }
    };
    let weighted = _mm256_cmp_ps::<_CMP_GT_OQ>(load(weight), zero);
    let (mut r, mut slot) = (0, runs.first().map_or(0, |run| run.0));
    while r < runs.len() {
        let mut n = 0;
        while r < runs.len() && n < HIT_BATCH {
            let end = runs[r].1;
            while slot < end && n < HIT_BATCH {
                let (_, d2) = offset_to(sorted, slot, hx, hy, hz);
                let inside = _mm256_and_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(d2, r2), m);
                hits[n] = slot;
                n += (_mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(inside, zero)) != 0) as usize;
                slot += 1;
            }
            if slot >= end {
                r += 1;
                slot = runs.get(r).map_or(0, |run| run.0);
            }
        }
        let mut counted = false;
        if !limited {
            limited = true;
            let strength = |slot| wet.as_deref().map_or_else(|| s.of(slot), |w| w.strength(slot));
            if r < runs.len() {
                // More within reach than one list holds: the lane form's count over the runs.
                share = load(&limit.row_weights(x, weight, inv_mass, runs, sorted, strength));
            } else if limit.counts(n as u32) {
                // `PullLimit::row_weights` over the list (the particles left out add nothing
                // to any lane's sum: the same bits), with each pair's terms kept for its pull.
                let mut sum = zero;
                for (k, &slot) in hits[..n].iter().enumerate() {
                    let (_, d2) = offset_to(sorted, slot, hx, hy, hz);
                    let t = shell_terms(d2);
                    let within = _mm256_cmp_ps::<_CMP_LE_OQ>(d2, r2);
                    let keep = _mm256_and_ps(within, _mm256_cmp_ps::<_CMP_GE_OQ>(d2, min2));
                    let stiff = _mm256_mul_ps(_mm256_set1_ps(strength(slot)), _mm256_and_ps(t.stiff, keep));
                    let inside = _mm256_and_ps(within, weighted);
                    sum = _mm256_add_ps(sum, _mm256_and_ps(stiff, inside));
                    terms[k].write(t);
                }
                let mut stiffness = [0.0f32; W];
                // SAFETY: `stiffness` holds W = 8 f32.
                unsafe { _mm256_storeu_ps(stiffness.as_mut_ptr(), sum) };
                share = load(&limit.limited(weight, inv_mass, &stiffness));
                counted = true;
            }
        }
        for (k, &slot) in hits[..n].iter().enumerate() {
            let ((dx, dy, dz), d2) = offset_to(sorted, slot, hx, hy, hz);
            let within = _mm256_cmp_ps::<_CMP_LE_OQ>(d2, r2);
            // The mask's 0 or 1 where within r_max, else 0 (the lane form's `inside`).
            let inside = _mm256_and_ps(within, m);
            marks = _mm256_max_ps(marks, inside);
            let s_j = match wet.as_deref_mut() {
                Some(w) => {
                    let (mut d2s, mut ins) = ([0.0f32; W], [0.0f32; W]);
                    // SAFETY: both arrays hold W = 8 f32.
                    unsafe {
                        _mm256_storeu_ps(d2s.as_mut_ptr(), d2);
                        _mm256_storeu_ps(ins.as_mut_ptr(), inside);
                    }
                    w.demand(slot, &d2s, &ins, r_min, r_max);
                    w.strength(slot)
                }
                None => s.of(slot),
            };
            // `force_scale`: s g(d) / d inside the reach and above MIN_DISTANCE, else 0.
            let Terms { d, shell, stiff } = if counted {
                // SAFETY: the count wrote the terms of each of the `n` listed particles.
                unsafe { terms[k].assume_init() }
            } else {
                shell_terms(d2)
            };
            let v = _mm256_div_ps(_mm256_mul_ps(_mm256_set1_ps(s_j), shell), d);
            let keep = _mm256_and_ps(within, _mm256_cmp_ps::<_CMP_GE_OQ>(d2, min2));
            let scale = _mm256_mul_ps(_mm256_and_ps(v, keep), share);
            let (fx, fy, fz) = (
                _mm256_mul_ps(scale, dx),
                _mm256_mul_ps(scale, dy),
                _mm256_mul_ps(scale, dz),
            );
            ax = _mm256_add_ps(ax, fx);
            ay = _mm256_add_ps(ay, fy);
            az = _mm256_add_ps(az, fz);
            // The forces' lane sums negated, and the stiffness's; each lane's times its bundle
            // in a guide groom.
            let stiff = _mm256_mul_ps(_mm256_and_ps(stiff, keep), share);
            let (rx, ry, rz, rs) = match bundle {
                None => (fx, fy, fz, stiff),
                Some(b) => (
                    _mm256_mul_ps(fx, b),
                    _mm256_mul_ps(fy, b),
                    _mm256_mul_ps(fz, b),
                    _mm256_mul_ps(stiff, b),
                ),
            };
            let sums = _mm_xor_ps(hsum4(rx, ry, rz, rs), _mm_setr_ps(-0.0, -0.0, -0.0, 0.0));
            let mut r = [0.0f32; 4];
            // SAFETY: `r` holds 4 f32.
            unsafe { _mm_storeu_ps(r.as_mut_ptr(), sums) };
            reactions.push(Reaction {
                slot,
                f: [r[0], r[1], r[2]],
                stiffness: r[3],
            });
        }
    }
    // SAFETY: each destination holds W = 8 f32.
    unsafe {
        _mm256_storeu_ps(near.as_mut_ptr(), marks);
        _mm256_storeu_ps(acc.x.as_mut_ptr(), ax);
        _mm256_storeu_ps(acc.y.as_mut_ptr(), ay);
        _mm256_storeu_ps(acc.z.as_mut_ptr(), az);
    }
}

#[cfg(test)]
mod tests {
    use super::super::absorb::{Demand, WetRow};
    use super::super::adhesion::{self, Reaction, Strength};
    use super::super::lanes::{Lane, L3, W};
    use super::super::pull_limit::PullLimit;
    use crate::scenes::Lcg;

    /// What one gather produced: the reactions, the forces on the lanes, the marks and the
    /// absorption demands.
    type Out = (Vec<Reaction>, L3, Lane, Vec<Demand>);
    /// A row's water and capacities, quanta.
    type WaterRow = ([u32; W], [u32; W]);

    /// Runs one row's gather over two runs of `q` (slots 2..5 and 7..), the lane form or the
    /// AVX2 one, from the same starting accumulators.
    #[allow(clippy::too_many_arguments)]
    fn gather(
        avx2: bool,
        x: &L3,
        mask: &Lane,
        weight: &Lane,
        bundle: Option<&Lane>,
        inv_mass: &Lane,
        limit: &PullLimit,
        q: &[Vec<f32>; 3],
        wet: Option<(&[u32], &WaterRow)>,
    ) -> Out {
        let (r_min, r_max, s) = (0.002f32, 0.008f32, 0.008f32);
        let runs = [(2, 5), (7, q[0].len() as u32)];
        let sorted = [&q[0][..], &q[1][..], &q[2][..]];
        let (mut reactions, mut demands) = (vec![], vec![]);
        let mut acc = L3::ZERO;
        acc.x[3] = 0.25; // accumulators carry what earlier rows' passes added
        let mut near = [0.0f32; W];
        near[5] = 1.0;
        let mut row = wet.map(|(mass, (water, hold))| WetRow {
            mass,
            strength_per_quantum: 1.0e-6,
            water,
            hold,
            share: &[1.0, 0.5, 2.0, 1.0, 0.25, 1.0, 1.5, 20.0],
            sat: None,
            first_point: 48,
            take: crate::physics::wet::absorb_take(30.0, 1.0 / 240.0),
            out: &mut demands,
        });
        // Both forms have one signature: the AVX2 one as an unsafe fn, the lane form coerced.
        type Gather = unsafe fn(
            &L3,
            &Lane,
            &Lane,
            Option<&Lane>,
            &Lane,
            &PullLimit,
            &[(u32, u32)],
            [&[f32]; 3],
            &mut Vec<Reaction>,
            &mut L3,
            &mut Lane,
            f32,
            f32,
            Strength<'_>,
            Option<&mut WetRow>,
        );
        let gather: Gather = if avx2 {
            super::gather_row_lanes
        } else {
            adhesion::gather_row_lanes
        };
        // SAFETY: the AVX2 form runs only after the caller asserted AVX2.
        unsafe {
            gather(
                x,
                mask,
                weight,
                bundle,
                inv_mass,
                limit,
                &runs,
                sorted,
                &mut reactions,
                &mut acc,
                &mut near,
                r_min,
                r_max,
                Strength::uniform(s),
                row.as_mut(),
            )
        };
        (reactions, acc, near, demands)
    }

    /// Every output as bits, one list (lengths first, so outputs of other sizes differ).
    fn bits(o: &Out) -> Vec<u32> {
        let mut v = vec![o.0.len() as u32, o.3.len() as u32];
        v.extend(o.0.iter().flat_map(|r| {
            [
                r.slot,
                r.f[0].to_bits(),
                r.f[1].to_bits(),
                r.f[2].to_bits(),
                r.stiffness.to_bits(),
            ]
        }));
        v.extend([o.1.x, o.1.y, o.1.z, o.2].concat().iter().map(|f| f.to_bits()));
        v.extend(o.3.iter().flat_map(|d| [d.slot, d.point, d.quanta]));
        v
    }

    /// The AVX2 gather gives the lane form's bits: particles inside r_min, in the shell, at
    /// r_max, beyond it and on a hair point; lanes masked out; pulls per point and per length;
    /// dry and absorbing; each point for itself and a guide groom's bundles.
    #[test]
    fn avx2_gives_the_lane_forms_bits() {
        assert!(
            crate::cpu::avx2::cpu_has_avx2(),
            "this test checks the AVX2 build: run it on a CPU with AVX2"
        );
        let mut rng = Lcg(5);
        let (mut reactions, mut demands, mut limited) = (0, 0, 0);
        for case in 0..300 {
            let mut x = L3::ZERO;
            let mut mask = [1.0f32; W];
            // Per point (the mask) in two cases of three, else per length: uneven shares.
            let mut weight = [1.0f32; W];
            // Saturations from 0 to 1.2 (water over capacity asks for nothing).
            let (mut water, mut capacity) = ([0u32; W], [0u32; W]);
            for l in 0..W {
                x.set(
                    l,
                    glam::Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.02,
                );
                mask[l] = (rng.next_f32() > 0.2) as u32 as f32;
                weight[l] = mask[l]
                    * if case % 3 == 2 {
                        0.25 + 2.0 * rng.next_f32()
                    } else {
                        1.0
                    };
                capacity[l] = 1000 + (rng.next_f32() * 4000.0) as u32;
                water[l] = (rng.next_f32() * 1.2 * capacity[l] as f32) as u32;
            }
            // Some rows with more particles within reach than the AVX2 form lists at once.
            let n = if case % 10 == 9 { 70 + case % 31 } else { 8 + case % 13 };
            let mut q = [vec![], vec![], vec![]];
            for j in 0..n {
                let p = match j % 4 {
                    // On a hair point (below MIN_DISTANCE) or exactly r_max from one.
                    0 => x.get(j % W),
                    1 => x.get(j % W) + glam::Vec3::new(0.008, 0.0, 0.0),
                    _ => glam::Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.02,
                };
                for (k, c) in q.iter_mut().enumerate() {
                    c.push(p[k]);
                }
            }
            let mass: Vec<u32> = (0..n + 7).map(|k| (k as u32 * 977) % 4000).collect();
            // Inverse masses from a paper-scene point's (1 g) to a real groom's (10 mg) and
            // pinned (0), so that the stability limit holds some lanes and not others.
            let inv_mass: Lane = std::array::from_fn(|l| [1.0e3, 1.0e5, 0.0, 3.0e4][(l + case) % 4]);
            let h = 1.0 / (60.0 * (1 + case % 8) as f32);
            // A guide groom's bundles in one case of four (padding lanes keep 1).
            let bundles: Lane = std::array::from_fn(|l| 1.0 + 39.0 * rng.next_f32() * mask[l]);
            let bundle = (case % 4 == 1).then_some(&bundles);
            for wet in [None, Some((&mass[..], &(water, capacity)))] {
                let heaviest = (0..W).map(|l| weight[l] * inv_mass[l]).fold(0.0, f32::max);
                let limit = PullLimit::new(h, 0.002, 0.008, wet.is_none().then_some(0.008), heaviest);
                let (a, b) = (
                    gather(false, &x, &mask, &weight, bundle, &inv_mass, &limit, &q, wet),
                    gather(true, &x, &mask, &weight, bundle, &inv_mass, &limit, &q, wet),
                );
                (reactions, demands) = (reactions + a.0.len(), demands + a.3.len());
                assert_eq!(bits(&a), bits(&b), "case {case}, wet {}", wet.is_some());
                let sorted = [&q[0][..], &q[1][..], &q[2][..]];
                let runs = [(2, 5), (7, n as u32)];
                let held = limit.row_weights(&x, &weight, &inv_mass, &runs, sorted, |_| 0.008);
                limited += (held != weight) as u32;
            }
        }
        // The cases reach the force, the absorption and the stability limit, not only the
        // rejections.
        assert!(
            reactions > 500 && demands > 200 && limited > 100,
            "{reactions} reactions, {demands} demands, {limited} rows limited"
        );
    }
}
