//! A row's coordinates loaded as vectors, and [`L3::bounds_of`] in AVX2 intrinsics, for the
//! CPU kernel's AVX2 build: the lanes' bounds by two vector selects and three vector min (or
//! max) steps per coordinate, where the lane form compiled to a select and a compare per lane
//! (the paper scene with 1,000 particles, one thread: 4.27 -> 4.18 ms a frame).

use super::lanes::{Lane, L3};
use glam::Vec3;
use std::arch::x86_64::*;

/// A row's three coordinates as three vectors.
///
/// # Safety
/// The CPU must support AVX2 (callers check `is_x86_feature_detected!("avx2")` once).
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn load(x: &L3) -> (__m256, __m256, __m256) {
    // SAFETY: each lane array is W = 8 contiguous f32; unaligned loads take any address.
    unsafe {
        (
            _mm256_loadu_ps(x.x.as_ptr()),
            _mm256_loadu_ps(x.y.as_ptr()),
            _mm256_loadu_ps(x.z.as_ptr()),
        )
    }
}

/// The lanes' smallest and largest coordinates (as [`L3::bounds_of`], the same bits: each
/// step is `a < b ? a : b`, the instruction's own rule) and the mask `1.0` on the lanes whose
/// bit is set in `lanes`, `0.0` elsewhere.
///
/// # Safety
/// The CPU must support AVX2 (callers check `is_x86_feature_detected!("avx2")` once).
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn bounds_and_mask(x: &L3, lanes: u32) -> (Vec3, Vec3, Lane) {
    let bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let on = _mm256_castsi256_ps(_mm256_cmpeq_epi32(
        _mm256_and_si256(_mm256_set1_epi32(lanes as i32), bit),
        bit,
    ));
    let (inf, ninf) = (_mm256_set1_ps(f32::INFINITY), _mm256_set1_ps(f32::NEG_INFINITY));
    // Lanes l and l + 4, then l and l + 2, then 0 and 1: `L3::bounds_of`'s order.
    let low = |v: __m256| -> f32 {
        let a = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
        let b = _mm_min_ps(a, _mm_movehl_ps(a, a));
        _mm_cvtss_f32(_mm_min_ss(b, _mm_shuffle_ps::<1>(b, b)))
    };
    let high = |v: __m256| -> f32 {
        let a = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
        let b = _mm_max_ps(a, _mm_movehl_ps(a, a));
        _mm_cvtss_f32(_mm_max_ss(b, _mm_shuffle_ps::<1>(b, b)))
    };
    let (px, py, pz) = load(x);
    let lo = |p: __m256| low(_mm256_blendv_ps(inf, p, on));
    let hi = |p: __m256| high(_mm256_blendv_ps(ninf, p, on));
    let mut mask = [0.0f32; 8];
    // SAFETY: `mask` holds 8 f32.
    unsafe { _mm256_storeu_ps(mask.as_mut_ptr(), _mm256_and_ps(on, _mm256_set1_ps(1.0))) };
    (
        Vec3::new(lo(px), lo(py), lo(pz)),
        Vec3::new(hi(px), hi(py), hi(pz)),
        mask,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::lanes::W;

    /// The same bits as the lane form, on every lane subset, with NaN, infinities and signed
    /// zeros among the coordinates.
    #[test]
    fn bounds_give_the_lane_forms_bits() {
        assert!(
            crate::cpu::avx2::cpu_has_avx2(),
            "this test checks the AVX2 build: run it on a CPU with AVX2"
        );
        let mut rng = crate::scenes::Lcg(3);
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.0, -0.0];
        for case in 0..64 {
            let mut x = L3::ZERO;
            for l in 0..W {
                let mut v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
                if case % 4 == 0 && l == case % W {
                    v.y = odd[case / 4 % odd.len()];
                }
                x.set(l, v);
            }
            for lanes in 0..256u32 {
                let (lo, hi) = x.bounds_of(lanes);
                // SAFETY: asserted above.
                let (lo2, hi2, mask) = unsafe { bounds_and_mask(&x, lanes) };
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(
                    (bits(lo), bits(hi)),
                    (bits(lo2), bits(hi2)),
                    "case {case}, lanes {lanes:08b}"
                );
                for (l, m) in mask.iter().enumerate() {
                    assert_eq!(*m, (lanes >> l & 1) as f32);
                }
            }
        }
    }
}
