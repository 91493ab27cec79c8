//! Pass `cohesion` on the CPU (docs/WET_MODEL.md §5): each wet point's pull toward its bridged
//! neighbours, `c (1 - r / d_b) (x_j - x_i)` for `r < d_b`, summed in neighbour order. Eight
//! points at a time, lane by lane, with exactly the scalar law's operations in the scalar
//! order, so the result is bit for bit the one-point-at-a-time sum (a test checks it) while
//! the arithmetic runs eight wide.

use crate::physics::lanes::{L3, W};
use crate::physics::wet::{self, MAX_BRIDGES};
use glam::Vec3;

/// A wet point's mutual pairs: the other points' places among the wet points and each
/// bridge's coefficient, N/m, `n` of them (unused slots hold 0 and no stiffness).
#[derive(Debug, Clone, Copy)]
pub struct Pairs {
    /// The other points' places among the wet points.
    pub j: [u32; MAX_BRIDGES],
    /// Each bridge's coefficient, N/m.
    pub c: [f32; MAX_BRIDGES],
    /// How many slots are used.
    pub n: u32,
}

impl Pairs {
    /// No pair.
    pub const NONE: Pairs = Pairs {
        j: [0; MAX_BRIDGES],
        c: [0.0; MAX_BRIDGES],
        n: 0,
    };
}

/// The pull on one wet point `i` (positions `xs`, by place among the wet points).
#[inline(always)]
pub fn pull_one(i: usize, xs: &[Vec3], pairs: &[Pairs], d_b: f32) -> Vec3 {
    let (xi, pr) = (xs[i], &pairs[i]);
    let mut sum = Vec3::ZERO;
    for m in 0..pr.n as usize {
        let d = xs[pr.j[m] as usize] - xi;
        sum += d * wet::bridge_scale(pr.c[m], d.length(), d_b);
    }
    sum
}

/// Calls `put(i, pull)` for every wet point `i` in `range`, eight at a time where it can (the
/// CPU's AVX2 build when `avx2`), each pull equal bit for bit to [`pull_one`].
pub fn pull_range(
    range: std::ops::Range<usize>,
    xs: &[Vec3],
    pairs: &[Pairs],
    d_b: f32,
    avx2: bool,
    put: impl FnMut(usize, Vec3),
) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` comes from `is_x86_feature_detected!("avx2")` (see `cpu_has_avx2`).
        unsafe { pull_range_avx2(range, xs, pairs, d_b, put) };
        return;
    }
    let _ = avx2;
    pull_range_lanes(range, xs, pairs, d_b, put)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pull_range_avx2(
    range: std::ops::Range<usize>,
    xs: &[Vec3],
    pairs: &[Pairs],
    d_b: f32,
    put: impl FnMut(usize, Vec3),
) {
    pull_range_lanes(range, xs, pairs, d_b, put)
}

#[inline(always)]
fn pull_range_lanes(
    range: std::ops::Range<usize>,
    xs: &[Vec3],
    pairs: &[Pairs],
    d_b: f32,
    mut put: impl FnMut(usize, Vec3),
) {
    let mut i = range.start;
    while i + W <= range.end {
        let mut xi = L3::ZERO;
        for k in 0..W {
            xi.set(k, xs[i + k]);
        }
        let mut sum = L3::ZERO;
        for m in 0..MAX_BRIDGES {
            let mut on = [false; W];
            for (k, on) in on.iter_mut().enumerate() {
                *on = m < pairs[i + k].n as usize;
            }
            if !on.iter().any(|&o| o) {
                break;
            }
            let (mut xj, mut c) = (L3::ZERO, [0.0f32; W]);
            for k in 0..W {
                let pr = &pairs[i + k];
                xj.set(k, xs[pr.j[m] as usize]);
                c[k] = pr.c[m];
            }
            // What `pull_one` does, lane by lane: glam's length is ((x x + y y) + z z).sqrt(),
            // and a slot past a point's count leaves its sum untouched.
            for k in 0..W {
                let (dx, dy, dz) = (xj.x[k] - xi.x[k], xj.y[k] - xi.y[k], xj.z[k] - xi.z[k]);
                let r = (dx * dx + dy * dy + dz * dz).sqrt();
                let s = wet::bridge_scale(c[k], r, d_b);
                let (ax, ay, az) = (sum.x[k] + dx * s, sum.y[k] + dy * s, sum.z[k] + dz * s);
                sum.x[k] = if on[k] { ax } else { sum.x[k] };
                sum.y[k] = if on[k] { ay } else { sum.y[k] };
                sum.z[k] = if on[k] { az } else { sum.z[k] };
            }
        }
        for k in 0..W {
            put(i + k, sum.get(k));
        }
        i += W;
    }
    for i in i..range.end {
        put(i, pull_one(i, xs, pairs, d_b));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eight-wide pass gives exactly the one-point sums, on any mix of pair counts,
    /// distances past `d_b` and coincident points.
    #[test]
    fn eight_wide_pulls_equal_the_scalar_bit_for_bit() {
        let mut seed = 7u32;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        let n = 203;
        let xs: Vec<Vec3> = (0..n)
            .map(|i| {
                if i % 17 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new(next(), next(), next()) * 0.01
                }
            })
            .collect();
        let pairs: Vec<Pairs> = (0..n)
            .map(|_| {
                let mut p = Pairs::NONE;
                p.n = (next() * 7.0) as u32 % 7;
                for m in 0..p.n as usize {
                    p.j[m] = (next() * n as f32) as u32 % n as u32;
                    p.c[m] = next() * 50.0;
                }
                p
            })
            .collect();
        let d_b = 0.008;
        for avx2 in [false, super::super::avx2::cpu_has_avx2()] {
            let mut got = vec![Vec3::NAN; n];
            pull_range(3..n, &xs, &pairs, d_b, avx2, |i, f| got[i] = f);
            let mut pulled = 0;
            for i in 3..n {
                let want = pull_one(i, &xs, &pairs, d_b);
                assert_eq!(
                    got[i].to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits),
                    "point {i}"
                );
                pulled += (want != Vec3::ZERO) as usize;
            }
            assert!(pulled > n / 2, "most points are pulled ({pulled})");
        }
    }
}
