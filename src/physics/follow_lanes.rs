//! The follower law of [`super::follow`] eight at a time: a guide point's frame for eight
//! guides at once ([`guide_frame_lanes`], a row of the CPU's lane layout), and eight
//! consecutive points of one follower ([`follow_lanes`]) where every guide it reads has the
//! follower's point count (point for point: most grooms). The same operations in the same
//! order as [`guide_frame`](super::follow::guide_frame),
//! [`follow_point`](super::follow::follow_point) and [`rotate`](super::follow::rotate), lane by
//! lane, so the same bits (the tests hold each lane to the one-point law); the CPU's follower
//! output (`cpu/followers.rs`, `cpu/follower_output.rs`) runs them and keeps the one-point law
//! for strands bound to guides of another length.

use super::follow::TURN_EPS;
use super::followers::Follow;
use super::lanes::{Lane, L3, W};
use glam::Vec4;

/// Eight consecutive points of one guide: positions, wetness, frames (xyzw quaternion
/// components) and rest positions (head space), as lanes.
#[derive(Clone, Copy, Debug, Default)]
pub struct GuideLanes {
    /// Positions.
    pub x: L3,
    /// Wetness.
    pub w: Lane,
    /// Frames: x, y, z, w.
    pub q: [Lane; 4],
    /// Rest positions.
    pub r: L3,
}

/// `v` turned by the unit quaternions `q`, lane by lane: `v + w t + q⃗ × t` with
/// `t = 2 q⃗ × v`.
#[inline(always)]
pub fn rotate_lanes(q: &[Lane; 4], v: &L3) -> L3 {
    let mut out = L3::ZERO;
    for l in 0..W {
        let (qx, qy, qz, qw) = (q[0][l], q[1][l], q[2][l], q[3][l]);
        let (vx, vy, vz) = (v.x[l], v.y[l], v.z[l]);
        let tx = 2.0 * (qy * vz - qz * vy);
        let ty = 2.0 * (qz * vx - qx * vz);
        let tz = 2.0 * (qx * vy - qy * vx);
        out.x[l] = (vx + qw * tx) + (qy * tz - qz * ty);
        out.y[l] = (vy + qw * ty) + (qz * tx - qx * tz);
        out.z[l] = (vz + qw * tz) + (qx * ty - qy * tx);
    }
    out
}

/// A rotation in every lane.
#[inline(always)]
pub fn splat_quat(q: Vec4) -> [Lane; 4] {
    [[q.x; W], [q.y; W], [q.z; W], [q.w; W]]
}

/// [`guide_frame`](super::follow::guide_frame) for eight guides' points at once, each with an
/// arriving segment from rest `rest_a` → `rest_b` and now `x_a` → `x_b`: each lane's starting
/// rotation `hq` (the head's, or with skinned roots its guide's root frame), then the
/// segment's smallest turn; lanes whose segment is degenerate (or turned by about 180 degrees)
/// keep the starting rotation, selected by bit masks (no branch per lane).
#[inline(always)]
pub fn guide_frame_lanes(hq: &[Lane; 4], rest_a: &L3, rest_b: &L3, x_a: &L3, x_b: &L3) -> [Lane; 4] {
    let d = L3 {
        x: std::array::from_fn(|l| rest_b.x[l] - rest_a.x[l]),
        y: std::array::from_fn(|l| rest_b.y[l] - rest_a.y[l]),
        z: std::array::from_fn(|l| rest_b.z[l] - rest_a.z[l]),
    };
    let a = rotate_lanes(hq, &d);
    let mut out = *hq;
    for l in 0..W {
        // `unit` of both directions, as masks: all ones where the length is usable.
        let unit = |x: f32, y: f32, z: f32| {
            let len2 = x * x + y * y + z * z;
            let ok = (len2 > 0.0) & (len2 < f32::INFINITY);
            let inv = 1.0 / if ok { len2 } else { 1.0 }.sqrt();
            ((x * inv, y * inv, z * inv), ok)
        };
        let ((ax, ay, az), ok_a) = unit(a.x[l], a.y[l], a.z[l]);
        let ((bx, by, bz), ok_b) = unit(x_b.x[l] - x_a.x[l], x_b.y[l] - x_a.y[l], x_b.z[l] - x_a.z[l]);
        let c = ax * bx + ay * by + az * bz;
        let turn = ok_a & ok_b & (1.0 + c >= TURN_EPS);
        let (qx, qy, qz, qw) = (ay * bz - by * az, az * bx - bz * ax, ax * by - bx * ay, 1.0 + c);
        let len2 = qx * qx + qy * qy + qz * qz + qw * qw;
        let inv = 1.0 / if turn { len2 } else { 1.0 }.sqrt();
        let (qx, qy, qz, qw) = (qx * inv, qy * inv, qz * inv, qw * inv);
        // quat_mul(q, head): (h⃗ q_w + q⃗ h_w + q⃗ × h⃗, q_w h_w - q⃗ · h⃗).
        let (hx, hy, hz, hw) = (hq[0][l], hq[1][l], hq[2][l], hq[3][l]);
        let m = [
            hx * qw + qx * hw + (qy * hz - hy * qz),
            hy * qw + qy * hw + (qz * hx - hz * qx),
            hz * qw + qz * hw + (qx * hy - hx * qy),
            qw * hw - (qx * hx + qy * hy + qz * hz),
        ];
        let keep = 0u32.wrapping_sub(turn as u32);
        for (o, m) in out.iter_mut().zip(m) {
            o[l] = f32::from_bits((m.to_bits() & keep) | (o[l].to_bits() & !keep));
        }
    }
    out
}

/// `from_guide` point for point: the guide's points and the follower's rest offsets `rest`
/// turned by the guide's frames.
#[inline(always)]
fn offsets(g: &GuideLanes, rest: &L3) -> L3 {
    let d = L3 {
        x: std::array::from_fn(|l| rest.x[l] - g.r.x[l]),
        y: std::array::from_fn(|l| rest.y[l] - g.r.y[l]),
        z: std::array::from_fn(|l| rest.z[l] - g.r.z[l]),
    };
    rotate_lanes(&g.q, &d)
}

/// [`follow_point`](super::follow::follow_point) for eight consecutive points whose rest
/// positions are `rest`, following `f` over the guides' lanes `g` (one per slot of `f`):
/// positions and weighted wetness.
#[inline(always)]
pub fn follow_lanes(f: &Follow, g: [&GuideLanes; 3], rest: &L3, clump: f32) -> (L3, Lane) {
    let d0 = offsets(g[0], rest);
    let mut x = L3::ZERO;
    let mut wet = [0.0f32; W];
    let mut shift = [0.0f32; W];
    let f0 = f.weights[0];
    for l in 0..W {
        let s0 = g[0].w[l];
        shift[l] = clump * s0;
        let w0 = f0 + shift[l] * (1.0 - f0);
        let k = 1.0 - clump * s0;
        x.x[l] = (g[0].x.x[l] + d0.x[l] * k) * w0;
        x.y[l] = (g[0].x.y[l] + d0.y[l] * k) * w0;
        x.z[l] = (g[0].x.z[l] + d0.z[l] * k) * w0;
        wet[l] = s0 * w0;
    }
    for (slot, gk) in g.iter().enumerate().skip(1) {
        let fk = f.weights[slot];
        if fk == 0.0 {
            continue;
        }
        let d = offsets(gk, rest);
        for l in 0..W {
            let s = gk.w[l];
            let w = fk * (1.0 - shift[l]);
            let k = 1.0 - clump * s;
            x.x[l] += (gk.x.x[l] + d.x[l] * k) * w;
            x.y[l] += (gk.x.y[l] + d.y[l] * k) * w;
            x.z[l] += (gk.x.z[l] + d.z[l] * k) * w;
            wet[l] += s * w;
        }
    }
    (x, wet)
}

/// [`output_point`](super::follow::output_point)'s blend, lane by lane: `old` moved to `now`
/// by `a` (positions as [`mix`](super::follow::mix), wetness likewise).
#[inline(always)]
pub fn blend_lanes(old: &(L3, Lane), now: &(L3, Lane), a: f32) -> (L3, Lane) {
    let m = |p: &Lane, q: &Lane| -> Lane { std::array::from_fn(|l| p[l] * (1.0 - a) + q[l] * a) };
    (
        L3 {
            x: m(&old.0.x, &now.0.x),
            y: m(&old.0.y, &now.0.y),
            z: m(&old.0.z, &now.0.z),
        },
        m(&old.1, &now.1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::follow::{follow_point, mix, GuidePoint};
    use crate::physics::followers::GuideSpan;
    use crate::scenes::Lcg;
    use glam::{Vec3, Vec4};

    /// Each lane's frame is the one-point law's bits, degenerate segments (zero, reversed)
    /// included.
    #[test]
    fn each_lane_frame_is_the_one_point_frame() {
        use crate::physics::follow::{guide_frame, head_quat};
        let mut rng = Lcg(9);
        let mut r = || rng.next_f32() * 2.0 - 1.0;
        for case in 0..200 {
            // One rotation for every lane (the head's), or one per lane (skinned roots).
            let mut heads = [Vec4::ZERO; W];
            for l in 0..W {
                heads[l] = if case % 2 == 1 && l > 0 {
                    heads[0]
                } else {
                    head_quat(glam::Quat::from_axis_angle(
                        Vec3::new(r(), r(), r()).normalize(),
                        3.0 * r(),
                    ))
                };
            }
            let mut hq = splat_quat(heads[0]);
            for (l, h) in heads.iter().enumerate() {
                for (c, v) in hq.iter_mut().zip(h.to_array()) {
                    c[l] = v;
                }
            }
            let mut seg = [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); W];
            for (l, s) in seg.iter_mut().enumerate() {
                let head = heads[l];
                let (ra, rb, xa) = (
                    Vec3::new(r(), r(), r()),
                    Vec3::new(r(), r(), r()),
                    Vec3::new(r(), r(), r()),
                );
                let turned = crate::physics::follow::rotate(head, rb - ra);
                let xb = match (case + l) % 6 {
                    0 => xa,                       // a zero segment now
                    1 => xa - turned * 2.0,        // exactly reversed
                    2 => xa + turned,              // not turned
                    _ => Vec3::new(r(), r(), r()), // anywhere
                };
                let rb = if (case + l) % 7 == 0 { ra } else { rb }; // a zero rest segment
                *s = (ra, rb, xa, xb);
            }
            let lanes = |k: usize| {
                let mut v = L3::ZERO;
                for (l, s) in seg.iter().enumerate() {
                    v.set(l, [s.0, s.1, s.2, s.3][k]);
                }
                v
            };
            let got = guide_frame_lanes(&hq, &lanes(0), &lanes(1), &lanes(2), &lanes(3));
            for (l, s) in seg.iter().enumerate() {
                let want = guide_frame(heads[l], Some(*s)).to_array().map(f32::to_bits);
                let have = [got[0][l], got[1][l], got[2][l], got[3][l]].map(f32::to_bits);
                assert_eq!(have, want, "case {case} lane {l}");
            }
        }
    }

    /// Each lane gives the one-point law's bits: random guides, frames, wetness, weights
    /// (including empty slots), clump, and a blend.
    #[test]
    fn each_lane_is_the_one_point_law() {
        let mut rng = Lcg(5);
        let mut r = || rng.next_f32() * 2.0 - 1.0;
        for case in 0..200 {
            let n = 8u32;
            // Three guides of n points each, in one guide-groom array.
            let points: Vec<GuidePoint> = (0..3 * n)
                .map(|_| {
                    let q = Vec4::new(r(), r(), r(), r()).normalize();
                    (Vec3::new(r(), r(), r()), r().abs(), q, Vec3::new(r(), r(), r()))
                })
                .collect();
            let spans: Vec<GuideSpan> = (0..3)
                .map(|g| GuideSpan {
                    first: g * n,
                    rest: 0,
                    count: n,
                    host: g,
                })
                .collect();
            let (a, b) = (r().abs(), r().abs());
            let weights = match case % 3 {
                0 => [1.0, 0.0, 0.0],
                1 => [a / (a + b), b / (a + b), 0.0],
                _ => [a / 2.0, b / 2.0, 1.0 - a / 2.0 - b / 2.0],
            };
            let f = Follow {
                guides: [2, 0, 1],
                weights,
            };
            let clump = r().abs();
            let rest: Vec<Vec3> = (0..n).map(|_| Vec3::new(r(), r(), r())).collect();
            let at = |p: u32| points[p as usize];
            let lanes = |g: u32| {
                let mut gl = GuideLanes::default();
                for l in 0..W {
                    let (x, w, q, rr) = points[(g * n) as usize + l];
                    gl.x.set(l, x);
                    gl.w[l] = w;
                    for (c, qc) in gl.q.iter_mut().zip(q.to_array()) {
                        c[l] = qc;
                    }
                    gl.r.set(l, rr);
                }
                gl
            };
            let g = [lanes(2), lanes(0), lanes(1)];
            let mut rest_l = L3::ZERO;
            for (l, &p) in rest.iter().enumerate() {
                rest_l.set(l, p);
            }
            let now = follow_lanes(&f, [&g[0], &g[1], &g[2]], &rest_l, clump);
            let old = follow_lanes(&Follow::own(0), [&g[1], &g[1], &g[1]], &rest_l, clump);
            let u = r().abs();
            let mixed = blend_lanes(&old, &now, u);
            for i in 0..n {
                let want = follow_point(&f, &spans, i, n, rest[i as usize], clump, &at);
                let l = i as usize;
                assert_eq!(
                    now.0.get(l).to_array().map(f32::to_bits),
                    want.0.to_array().map(f32::to_bits),
                    "case {case} lane {l}"
                );
                assert_eq!(now.1[l].to_bits(), want.1.to_bits(), "case {case} lane {l} wetness");
                let was = follow_point(&Follow::own(0), &spans, i, n, rest[l], clump, &at);
                let want_mix = (mix(was.0, want.0, u), was.1 * (1.0 - u) + want.1 * u);
                assert_eq!(
                    mixed.0.get(l).to_array().map(f32::to_bits),
                    want_mix.0.to_array().map(f32::to_bits)
                );
                assert_eq!(mixed.1[l].to_bits(), want_mix.1.to_bits());
            }
        }
    }
}
