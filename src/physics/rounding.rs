//! Floor and round by integer conversion. The crate's baseline x86-64 build has no SSE4.1
//! rounding instruction, so `f32::floor`, `f64::floor` and `f64::round` are calls into libm:
//! in the wet step's flow, drying and hair-grid passes they were 3 % of the frame. These give
//! the same results as the library functions (bit for bit) on the ranges their callers use.

/// `x.floor() as u64` for `x >= 0` (NaN gives 0, above `u64::MAX` saturates), as the cast
/// truncates toward zero and truncation is the floor of a non-negative number.
#[inline(always)]
pub fn floor_nonneg(x: f64) -> u64 {
    x as u64
}

/// 2^52: from here on every f64 is an integer, and below it adding `TWO_52` and taking it
/// away again rounds a non-negative number to an integer.
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// Each lane's floor and its fraction's test, as vectors, when every lane is in `[0, limit)`
/// (`limit` at most `TWO_52 - 1`, so that a floor plus one stays in range): `round_up` says
/// whether a lane moves up by one after its floor. `None` where any lane is outside (NaN,
/// negative, huge: never in practice), for the caller's lane-by-lane path.
#[inline(always)]
fn small_integers<const N: usize>(x: &[f64; N], limit: f64, round_up: impl Fn(f64, f64) -> bool) -> Option<[u64; N]> {
    let mut fits = true;
    for &x in x {
        fits &= (0.0..limit).contains(&x);
    }
    if !fits {
        return None;
    }
    let mut out = [0u64; N];
    for (o, &x) in out.iter_mut().zip(x) {
        let near = (x + TWO_52) - TWO_52;
        let floor = if near > x { near - 1.0 } else { near };
        let v = if round_up(x, floor) { floor + 1.0 } else { floor };
        // An integer below 2^52 is the low mantissa bits of itself plus 2^52.
        *o = (v + TWO_52).to_bits() - TWO_52.to_bits();
    }
    Some(out)
}

/// [`floor_nonneg`] lane by lane, the same bits, in a form that runs as vectors: x86 has no
/// vector conversion of f64 to u64 before AVX-512, and the scalar ones were a fifth of the
/// wet step's flow pass.
#[inline(always)]
pub fn floor_nonneg_lanes<const N: usize>(x: &[f64; N]) -> [u64; N] {
    small_integers(x, TWO_52 - 1.0, |_, _| false).unwrap_or_else(|| x.map(floor_nonneg))
}

/// [`round_nonneg`] lane by lane, the same bits, as vectors: the floor, one up where the
/// dropped part is a half or more.
#[inline(always)]
pub fn round_nonneg_lanes<const N: usize>(x: &[f64; N]) -> [u64; N] {
    small_integers(x, TWO_52 - 1.0, |x, floor| x - floor >= 0.5).unwrap_or_else(|| x.map(round_nonneg))
}

/// `x.round() as u64` (half away from zero) for `x >= 0` (NaN gives 0, above `u64::MAX`
/// saturates). `x - trunc(x)` is exact in binary floating point, so the half test is exact.
#[inline(always)]
pub fn round_nonneg(x: f64) -> u64 {
    let t = x as u64;
    t.saturating_add((x - t as f64 >= 0.5) as u64)
}

/// `x.round() as i64` (half away from zero; NaN gives 0, beyond `i64` saturates): truncate
/// toward zero, then one away from zero where the dropped part is a half or more (exact, as
/// in [`round_nonneg`]).
#[inline(always)]
pub fn round_i64(x: f64) -> i64 {
    let t = x as i64;
    let frac = x - t as f64;
    t.saturating_add((frac >= 0.5) as i64)
        .saturating_sub((frac <= -0.5) as i64)
}

/// `v.floor() as i32` (NaN gives 0, beyond `i32` saturates): truncate toward zero, then one
/// down where that rounded a negative number up.
#[inline(always)]
pub fn floor_i32(v: f32) -> i32 {
    let t = v as i32;
    t.saturating_sub((v < t as f32) as i32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lanes_floor_and_round_as_each_lane_alone() {
        let edge = [
            0.0,
            -0.0,
            0.25,
            0.5,
            0.999_999_999_999_999_9,
            1.0,
            1.5,
            2.5,
            3.5,
            1e15 + 0.5,
            4_503_599_627_370_495.5,
            4_503_599_627_370_495.0,
            4_503_599_627_370_494.5,
            4_503_599_627_370_494.0,
            4_503_599_627_370_496.0,
            9_007_199_254_740_993.0,
            1e300,
            -1.0,
            f64::INFINITY,
            f64::NAN,
        ];
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for round in 0..20_000 {
            // Mostly lanes that fit, one edge value among them in some rounds.
            let mut x = [0.0f64; 8];
            for x in x.iter_mut() {
                *x = (next() >> 11) as f64 / (1u64 << 53) as f64 * 10f64.powi((next() % 16) as i32);
            }
            if round % 3 == 0 {
                x[(next() % 8) as usize] = edge[(next() % edge.len() as u64) as usize];
            }
            assert_eq!(floor_nonneg_lanes(&x), x.map(floor_nonneg), "{x:?}");
            assert_eq!(round_nonneg_lanes(&x), x.map(round_nonneg), "{x:?}");
        }
        for &e in &edge {
            assert_eq!(floor_nonneg_lanes(&[e; 8]), [floor_nonneg(e); 8], "{e}");
            assert_eq!(round_nonneg_lanes(&[e; 8]), [round_nonneg(e); 8], "{e}");
        }
    }

    #[test]
    fn equal_to_the_library_functions() {
        let mut xs: Vec<f64> = vec![
            0.0,
            0.25,
            0.5,
            0.49999999999999994,
            1.5,
            2.5,
            1e15 + 0.5,
            4503599627370495.5,
            9007199254740993.0,
            1e300,
            f64::INFINITY,
            f64::NAN,
        ];
        let mut s = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..100_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            xs.push(f64::from_bits(s).abs());
            xs.push((s >> 11) as f64 / (1u64 << 20) as f64);
        }
        for &x in &xs {
            assert_eq!(floor_nonneg(x), x.floor() as u64, "{x}");
            assert_eq!(round_nonneg(x), x.round() as u64, "{x}");
            assert_eq!(round_i64(x), x.round() as i64, "{x}");
            assert_eq!(round_i64(-x), (-x).round() as i64, "{x}");
        }
        let mut vs: Vec<f32> = vec![
            0.0,
            -0.0,
            -0.5,
            -1.0,
            1.0,
            2147483520.0,
            3e9,
            -2147483648.0,
            -3e9,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1e-45,
            1e-45,
        ];
        for _ in 0..100_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            vs.push(f32::from_bits(s as u32));
            vs.push(((s >> 40) as f32 - 8_388_608.0) / 1024.0);
        }
        for &v in &vs {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
        }
    }
}
