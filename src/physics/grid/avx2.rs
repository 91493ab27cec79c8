//! The grid's per-row prefilter ([`Grid::may_have_near_lanes`]) in AVX2 intrinsics, for the
//! CPU kernel's AVX2 build: the box test, the clamped fine cells and their index for all eight
//! lanes in a few vector instructions (LLVM kept the lane form's float-to-int conversions and
//! index arithmetic scalar). The same bits as the lane form; its test holds it to them.

use super::Grid;
use crate::physics::lanes::L3;
use std::arch::x86_64::*;

impl Grid {
    /// [`Grid::may_have_near_lanes`] on AVX2: a bit per lane, the same bits.
    ///
    /// # Safety
    /// The CPU must support AVX2 (callers check `is_x86_feature_detected!("avx2")` once).
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn may_have_near_lanes_avx2(&self, x: &L3, r: f32) -> u32 {
        debug_assert!(r <= self.cell_min);
        if self.filtered && self.near.is_empty() {
            return 0;
        }
        // SAFETY: this function's own AVX2 requirement.
        let (px, py, pz) = unsafe { crate::physics::lanes_avx2::load(x) };
        let (lo, hi) = (self.lo - r, self.hi + r);
        let within = |p: __m256, a: f32, b: f32| {
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(p, _mm256_set1_ps(a)),
                _mm256_cmp_ps::<_CMP_LE_OQ>(p, _mm256_set1_ps(b)),
            )
        };
        let inside = _mm256_and_ps(
            _mm256_and_ps(within(px, lo.x, hi.x), within(py, lo.y, hi.y)),
            within(pz, lo.z, hi.z),
        );
        let in_box = _mm256_movemask_ps(inside) as u32;
        if !self.filtered || in_box == 0 {
            return in_box;
        }
        // The fine cell per axis: ((p - lo) * inv) clamped to [0, top], truncated. The lane
        // form's `clamp` passes NaN through and `as i32` makes it 0; here `max` with 0 (its
        // second operand wins on NaN) makes it 0 first: the same cell.
        let inv = _mm256_set1_ps(self.fine_inv);
        let top = (self.fine_dims - glam::IVec3::ONE).as_vec3();
        let cell = |p: __m256, lo: f32, top: f32| {
            let c = _mm256_mul_ps(_mm256_sub_ps(p, _mm256_set1_ps(lo)), inv);
            let c = _mm256_min_ps(_mm256_max_ps(c, _mm256_setzero_ps()), _mm256_set1_ps(top));
            _mm256_cvttps_epi32(c)
        };
        let (cx, cy, cz) = (
            cell(px, self.lo.x, top.x),
            cell(py, self.lo.y, top.y),
            cell(pz, self.lo.z, top.z),
        );
        let (dy, dz) = (_mm256_set1_epi32(self.fine_dims.y), _mm256_set1_epi32(self.fine_dims.z));
        let idx = _mm256_add_epi32(
            _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(cx, dy), cy), dz),
            cz,
        );
        let mut lanes = [0u32; 8];
        // SAFETY: `lanes` holds 8 u32.
        unsafe { _mm256_storeu_si256(lanes.as_mut_ptr().cast(), idx) };
        let mut bits = 0u32;
        let mut left = in_box;
        while left != 0 {
            let l = left.trailing_zeros();
            left &= left - 1;
            let i = lanes[l as usize] as usize;
            // SAFETY: each coordinate is clamped to [0, fine_dims - 1], so i is below the
            // fine cell count, and `near` holds that many bits after a build.
            let flag = (unsafe { *self.near.get_unchecked(i / 64) } >> (i % 64)) as u32 & 1;
            bits |= flag << l;
        }
        bits
    }
}

#[cfg(test)]
mod tests {
    use crate::physics::grid::Grid;
    use crate::physics::lanes::{L3, W};
    use crate::scenes::Lcg;
    use glam::Vec3;

    /// The AVX2 prefilter gives the lane form's bits: rows in, out of and across the box,
    /// NaN lanes, with and without the fine bits, and for an empty grid.
    #[test]
    fn avx2_gives_the_lane_forms_bits() {
        assert!(
            crate::cpu::avx2::cpu_has_avx2(),
            "this test checks the AVX2 build: run it on a CPU with AVX2"
        );
        let mut rng = Lcg(9);
        let r = 0.008;
        let points: Vec<Vec3> = (0..200)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32() * 0.5) * 0.2)
            .collect();
        let (mut filtered, mut plain, mut empty) =
            (Grid::new(200, r), Grid::without_prefilter(200, r), Grid::new(200, r));
        filtered.build(&points);
        plain.build(&points);
        empty.build(&[]);
        let (mut passed, mut stopped) = (0, 0);
        for case in 0..4000 {
            let mut x = L3::ZERO;
            let centre = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.3 - 0.05;
            for l in 0..W {
                let jitter = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.02;
                x.set(l, if case % 97 == l { Vec3::NAN } else { centre + jitter });
            }
            for g in [&filtered, &plain, &empty] {
                let want = g.may_have_near_lanes(&x, r);
                // SAFETY: asserted above.
                let got = unsafe { g.may_have_near_lanes_avx2(&x, r) };
                assert_eq!(got, want, "case {case}");
                passed += want.count_ones();
                stopped += W as u32 - want.count_ones();
            }
        }
        assert!(
            passed > 5_000 && stopped > 5_000,
            "{passed} lanes passed, {stopped} stopped"
        );
    }
}
