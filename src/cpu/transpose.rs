//! The AVX2 layout of one row of vertex output: 8 lanes of 8 components become 8 vertices by an
//! 8 x 8 register transpose and one store per vertex (a float at a time costs a store and an
//! extract per float).

use super::output::STAGE;
use crate::physics::lanes::{Lane, W};
use std::arch::x86_64::*;

/// Writes `cols[k][l]` to `stage[l][at + k]` for all 8 components `k` and lanes `l`.
///
/// # Safety
/// AVX2 must be present.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn transpose_into(cols: &[Lane; 8], stage: &mut [[f32; STAGE]; W], at: usize) {
    assert!(at + 8 <= STAGE, "the stage holds the whole 8-float store");
    for (lane, v) in stage.iter_mut().zip(transpose(cols)) {
        // In bounds: the assert above.
        _mm256_storeu_ps(lane.as_mut_ptr().add(at), v);
    }
}

/// Writes `cols[k][l]` to `run[at + l * stride + k]` for all 8 components `k` and lanes `l`:
/// eight vertices of `stride` floats one after the other (each store also writes 8 - `stride`
/// floats past its vertex, which the next overwrites; the last one's stay past the eighth).
///
/// # Safety
/// AVX2 must be present.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn transpose_run(cols: &[Lane; 8], run: &mut [f32], at: usize, stride: usize) {
    assert!(at + 7 * stride + 8 <= run.len(), "the run holds the last 8-float store");
    for (l, v) in transpose(cols).into_iter().enumerate() {
        // In bounds: the assert above.
        _mm256_storeu_ps(run.as_mut_ptr().add(at + l * stride), v);
    }
}

/// The 8 x 8 transpose: vector `l` holds lane `l`'s 8 components.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn transpose(cols: &[Lane; 8]) -> [__m256; 8] {
    let r: [__m256; 8] = std::array::from_fn(|k| _mm256_loadu_ps(cols[k].as_ptr()));
    // Pairs, then quads within each 128-bit half, then halves across: lane l's 8 floats.
    let t0 = _mm256_unpacklo_ps(r[0], r[1]);
    let t1 = _mm256_unpackhi_ps(r[0], r[1]);
    let t2 = _mm256_unpacklo_ps(r[2], r[3]);
    let t3 = _mm256_unpackhi_ps(r[2], r[3]);
    let t4 = _mm256_unpacklo_ps(r[4], r[5]);
    let t5 = _mm256_unpackhi_ps(r[4], r[5]);
    let t6 = _mm256_unpacklo_ps(r[6], r[7]);
    let t7 = _mm256_unpackhi_ps(r[6], r[7]);
    let s0 = _mm256_shuffle_ps::<0x44>(t0, t2);
    let s1 = _mm256_shuffle_ps::<0xEE>(t0, t2);
    let s2 = _mm256_shuffle_ps::<0x44>(t1, t3);
    let s3 = _mm256_shuffle_ps::<0xEE>(t1, t3);
    let s4 = _mm256_shuffle_ps::<0x44>(t4, t6);
    let s5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
    let s6 = _mm256_shuffle_ps::<0x44>(t5, t7);
    let s7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
    [
        _mm256_permute2f128_ps::<0x20>(s0, s4),
        _mm256_permute2f128_ps::<0x20>(s1, s5),
        _mm256_permute2f128_ps::<0x20>(s2, s6),
        _mm256_permute2f128_ps::<0x20>(s3, s7),
        _mm256_permute2f128_ps::<0x31>(s0, s4),
        _mm256_permute2f128_ps::<0x31>(s1, s5),
        _mm256_permute2f128_ps::<0x31>(s2, s6),
        _mm256_permute2f128_ps::<0x31>(s3, s7),
    ]
}
