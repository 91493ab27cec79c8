//! SIMD-friendly lane types: `W` strands side by side, so that point `i` of `W` strands is one
//! vector operation. Plain arrays with fixed-length loops; LLVM turns them into SSE/AVX code.

/// Strands per lane group (one AVX register of f32).
pub const W: usize = 8;

/// One scalar per strand of a lane group.
pub type Lane = [f32; W];

/// One 3-vector per strand of a lane group, stored as three lanes (x, y, z).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct L3 {
    /// x components.
    pub x: Lane,
    /// y components.
    pub y: Lane,
    /// z components.
    pub z: Lane,
}

impl L3 {
    /// All components zero.
    pub const ZERO: L3 = L3 {
        x: [0.0; W],
        y: [0.0; W],
        z: [0.0; W],
    };

    /// The vector of lane `l`.
    #[inline(always)]
    pub fn get(&self, l: usize) -> glam::Vec3 {
        glam::Vec3::new(self.x[l], self.y[l], self.z[l])
    }

    /// Sets the vector of lane `l`.
    #[inline(always)]
    pub fn set(&mut self, l: usize, v: glam::Vec3) {
        self.x[l] = v.x;
        self.y[l] = v.y;
        self.z[l] = v.z;
    }

    /// Adds `v` to lane `l`.
    #[inline(always)]
    pub fn add_at(&mut self, l: usize, v: glam::Vec3) {
        self.x[l] += v.x;
        self.y[l] += v.y;
        self.z[l] += v.z;
    }

    /// `m` applied to each lane's point, as `Affine3A::transform_point3` computes it
    /// (`((x_axis x + y_axis y) + z_axis z) + translation`, no fused multiply-add): the same
    /// bits, eight lanes per vector operation where the per-lane calls ran one lane at a
    /// time.
    #[inline(always)]
    pub fn transformed(&self, m: &glam::Affine3A) -> L3 {
        let (a, b, c, t) = (m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis, m.translation);
        let row = |ax: f32, bx: f32, cx: f32, tx: f32| -> Lane {
            std::array::from_fn(|l| ((ax * self.x[l] + bx * self.y[l]) + cx * self.z[l]) + tx)
        };
        L3 {
            x: row(a.x, b.x, c.x, t.x),
            y: row(a.y, b.y, c.y, t.y),
            z: row(a.z, b.z, c.z, t.z),
        }
    }

    /// The smallest and largest coordinates over the lanes whose bit is set in `lanes`
    /// (infinities when none is), branch-free: a reduction in halves, so that neither a branch
    /// per lane nor a chain through eight lanes stands between a row and its grid query.
    /// Min and max are exact, so the result is the same whatever the order.
    #[inline(always)]
    pub fn bounds_of(&self, lanes: u32) -> (glam::Vec3, glam::Vec3) {
        let pick =
            |v: &Lane, fill: f32| -> Lane { std::array::from_fn(|l| if lanes >> l & 1 != 0 { v[l] } else { fill }) };
        let low = |v: Lane| -> f32 {
            let a: [f32; 4] = std::array::from_fn(|l| if v[l] < v[l + 4] { v[l] } else { v[l + 4] });
            let b: [f32; 2] = std::array::from_fn(|l| if a[l] < a[l + 2] { a[l] } else { a[l + 2] });
            if b[0] < b[1] {
                b[0]
            } else {
                b[1]
            }
        };
        let high = |v: Lane| -> f32 {
            let a: [f32; 4] = std::array::from_fn(|l| if v[l] > v[l + 4] { v[l] } else { v[l + 4] });
            let b: [f32; 2] = std::array::from_fn(|l| if a[l] > a[l + 2] { a[l] } else { a[l + 2] });
            if b[0] > b[1] {
                b[0]
            } else {
                b[1]
            }
        };
        let (inf, ninf) = (f32::INFINITY, f32::NEG_INFINITY);
        (
            glam::Vec3::new(
                low(pick(&self.x, inf)),
                low(pick(&self.y, inf)),
                low(pick(&self.z, inf)),
            ),
            glam::Vec3::new(
                high(pick(&self.x, ninf)),
                high(pick(&self.y, ninf)),
                high(pick(&self.z, ninf)),
            ),
        )
    }

    /// `self + a (to - self)`, lane by lane: the output blend between two steps' positions
    /// (`output.wgsl` `toward` is its GPU twin).
    #[inline(always)]
    pub fn toward(&self, to: &L3, a: f32) -> L3 {
        let f = |p: &Lane, x: &Lane| std::array::from_fn(|l| p[l] + a * (x[l] - p[l]));
        L3 {
            x: f(&self.x, &to.x),
            y: f(&self.y, &to.y),
            z: f(&self.z, &to.z),
        }
    }
}

/// Sum of the lanes in a fixed pairwise order (a tree the compiler can keep in registers, and
/// the same bits on every run).
#[inline(always)]
pub fn hsum(a: &Lane) -> f32 {
    let s4 = [a[0] + a[4], a[1] + a[5], a[2] + a[6], a[3] + a[7]];
    (s4[0] + s4[2]) + (s4[1] + s4[3])
}

/// 2^52 as an f64: its mantissa's low bits hold any `u32` exactly.
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// Each lane's `q as f64` (exact), in a form that runs as vectors: x86 before AVX-512 has no
/// conversion from unsigned integers, and with `as` LLVM left the held water's laws scalar
/// (eight conversions and eight divides a row). The count goes into the low mantissa bits
/// of 2^52, which is then taken away.
#[inline(always)]
pub fn u32_as_f64(q: &[u32; W]) -> [f64; W] {
    std::array::from_fn(|l| f64::from_bits(TWO_52.to_bits() | q[l] as u64) - TWO_52)
}

/// Each lane's `q as f32` (to nearest, as `as` rounds), as vectors: exact in f64 first, so
/// the one rounding to f32 is the same.
#[inline(always)]
pub fn u32_as_f32(q: &[u32; W]) -> Lane {
    u32_as_f64(q).map(|x| x as f32)
}

/// Mutable per-row state: positions (m) and velocities (m/s) of `W` points.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct StateRow {
    /// Positions, world space.
    pub x: L3,
    /// Velocities.
    pub v: L3,
}

/// Constant per-row parameters: the springs that start at this row and inverse masses.
/// The bend spring's stiffness and the inverse mass, which held water rewrites each step,
/// are last and side by side, so the rewrite dirties one cache line of a row in two and two
/// of the other (a row is 224 bytes), not two of each.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct ParamRow {
    /// Stretch spring from point i to i+1.
    pub stretch: super::spring::SpringLanes,
    /// Bend spring from point i to i+2.
    pub bend: super::spring::SpringLanes,
    /// Inverse mass, 1/kg; 0 for pinned points.
    pub inv_mass: Lane,
}

/// The rest segments point `i` of a block's `rows` ends in lane `l`, m: (before, after), 0
/// where the strand has none (row 0 has no segment before it; a strand's last point and its
/// padding have no stretch spring, so no rest length after). What the hair a point stands
/// for is reckoned from ([`super::per_length::PerLength::row`], [`super::wet::absorb_share`]).
#[inline(always)]
pub fn rest_segments(rows: &[ParamRow], i: usize, l: usize) -> (f32, f32) {
    let before = if i > 0 { rows[i - 1].stretch.rest[l] } else { 0.0 };
    (before, rows[i].stretch.rest[l])
}

// The bend spring's stiffness directly before the inverse mass (see `ParamRow`): fails the
// build if either struct's fields are reordered.
const _: () = assert!(
    std::mem::offset_of!(ParamRow, bend) + std::mem::offset_of!(super::spring::SpringLanes, k) + 32
        == std::mem::offset_of!(ParamRow, inv_mass)
);

#[cfg(test)]
mod tests {
    use super::{L3, W};
    use crate::scenes::Lcg;
    use glam::{Affine3A, Quat, Vec3};

    /// The lane conversions of `u32` give `as`'s values, at the ends of the range too.
    #[test]
    fn unsigned_conversions_give_the_casts_bits() {
        let mut rng = Lcg(5);
        let edges = [
            0,
            1,
            2,
            (1 << 24) - 1,
            1 << 24,
            (1 << 24) + 1,
            (1 << 31) - 1,
            1 << 31,
            u32::MAX - 1,
            u32::MAX,
        ];
        for k in 0..2000 {
            let q: [u32; W] = std::array::from_fn(|l| {
                if k < 2 * edges.len() {
                    edges[(k + l) % edges.len()]
                } else {
                    (rng.next_f32() * u32::MAX as f32) as u32 ^ (rng.next_f32() * 65536.0) as u32
                }
            });
            assert_eq!(super::u32_as_f64(&q).map(f64::to_bits), q.map(|q| (q as f64).to_bits()));
            assert_eq!(super::u32_as_f32(&q).map(f32::to_bits), q.map(|q| (q as f32).to_bits()));
        }
    }

    /// `transformed` gives `Affine3A::transform_point3`'s bits on every lane.
    #[test]
    fn transformed_gives_glams_bits() {
        let mut rng = Lcg(3);
        let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
        for _ in 0..500 {
            let m = Affine3A::from_scale_rotation_translation(v() + 1.0, Quat::from_scaled_axis(v() * 4.0), v() * 3.0);
            let mut p = L3::ZERO;
            for l in 0..W {
                p.set(l, v() * 0.7);
            }
            let t = p.transformed(&m);
            for l in 0..W {
                let want = m.transform_point3(p.get(l)).to_array().map(f32::to_bits);
                assert_eq!(t.get(l).to_array().map(f32::to_bits), want);
            }
        }
    }
}
