//! The follower law (docs/GUIDES.md), written once: each guide point's frame
//! ([`guide_frame`], once per guide point and output), then each follower point from its
//! guides ([`follow_point`]). The CPU backend's writer (`cpu/followers.rs`) and the seeding of
//! new guides (`sim/guides.rs`) call it; `follow.wgsl` and `write_followers.wgsl` mirror it function by function
//! (passes `guide_frames` and `write_followers`).

use super::followers::{Follow, Followers, GuideSpan};
use glam::{Quat, Vec3, Vec3A, Vec4};

/// `a` moved to `b` by `u` as `a (1 - u) + b u`, which gives `a` at 0 and `b` at 1 exactly.
#[inline]
pub fn mix(a: Vec3, b: Vec3, u: f32) -> Vec3 {
    a * (1.0 - u) + b * u
}

/// `v` turned by the unit quaternion `q` (`v + w t + q⃗ × t` with `t = 2 q⃗ × v`).
#[inline]
pub fn rotate(q: Vec4, v: Vec3) -> Vec3 {
    // In SSE lanes (`Vec3A`): the same products and sums, in the same order, as the scalar form.
    let (axis, v) = (Vec3A::from_vec4(q), Vec3A::from(v));
    let t = 2.0 * axis.cross(v);
    Vec3::from(v + q.w * t + axis.cross(t))
}

/// The quaternion product `a b` (turn by `b`, then by `a`), xyzw.
#[inline]
pub fn quat_mul(a: Vec4, b: Vec4) -> Vec4 {
    let (av, bv) = (a.truncate(), b.truncate());
    (bv * a.w + av * b.w + av.cross(bv)).extend(a.w * b.w - av.dot(bv))
}

/// `d` over its length, or `None` when that is zero or not finite.
#[inline]
pub fn unit(d: Vec3) -> Option<Vec3> {
    let len2 = d.dot(d);
    (len2 > 0.0 && len2 < f32::INFINITY).then(|| d * (1.0 / len2.sqrt()))
}

/// Below this `1 + a · b` a segment's turn is skipped (more than about 179 degrees: the
/// smallest rotation is not unique).
pub const TURN_EPS: f32 = 1e-4;

/// The frame a guide point carries: the head's rotation `head`, then the smallest rotation
/// from the rest direction `rest_b - rest_a` (turned by the head) of the guide segment that
/// arrives at the point to its current direction `x_b - x_a` (half-way quaternion
/// `(a × b, 1 + a · b)`, normalised). `None` (the root: no segment arrives) or a degenerate
/// segment gives the head's rotation alone.
#[inline]
pub fn guide_frame(head: Vec4, segment: Option<(Vec3, Vec3, Vec3, Vec3)>) -> Vec4 {
    let Some((rest_a, rest_b, x_a, x_b)) = segment else {
        return head;
    };
    let (Some(a), Some(b)) = (unit(rotate(head, rest_b - rest_a)), unit(x_b - x_a)) else {
        return head;
    };
    let c = a.dot(b);
    if 1.0 + c < TURN_EPS {
        return head;
    }
    let q = a.cross(b).extend(1.0 + c);
    // The squared length summed left to right (not `dot`, whose order is the SIMD's), so that
    // `follow_lanes::guide_frame_lanes` gives the same bits on every platform.
    let len2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    quat_mul(q * (1.0 / len2.sqrt()), head)
}

/// Guide point `j` of `span`'s frame from the guide groom's positions `x` (flat, guide-groom
/// order) and the host's rest pose `rest`.
#[inline]
pub fn guide_frame_at(span: GuideSpan, j: u32, rest: &[Vec3], head: Vec4, x: impl Fn(u32) -> Vec3) -> Vec4 {
    let seg = (j > 0).then(|| {
        let r = (span.rest + j) as usize;
        (rest[r - 1], rest[r], x(span.first + j - 1), x(span.first + j))
    });
    guide_frame(head, seg)
}

/// A guide point as the follower law reads it: position, wetness, frame, rest position (head
/// space; gathered with the rest so that a follower reads its guides' points from one place).
pub type GuidePoint = (Vec3, f32, Vec4, Vec3);

/// Where point `i` of a strand of `n` points falls on a strand of `m` points (at least 2) at
/// the same fraction of its length, `s = i (m - 1) / (n - 1)`: between points `j` and `j + 1`
/// (`j ≤ m - 2`), `u = s - j` of the way.
#[inline(always)]
pub fn same_fraction(i: u32, n: u32, m: u32) -> (u32, f32) {
    let s = (i * (m - 1)) as f32 / (n - 1).max(1) as f32;
    let j = (s as u32).min(m - 2);
    (j, s - j as f32)
}

/// Where guide `span` puts point `i` of a follower of `n` points whose rest position is
/// `rest_i`: the guide's point at the same fraction of its length (`s = i (m - 1) / (n - 1)`
/// for a guide of `m` points, between its points `j` and `j + 1`, `u = s - j`), the follower's
/// rest offset from there turned by the frame of the guide point the arriving segment ends at
/// (`j + 1` inside a segment, `j` on a point), and the guide's wetness there. `at(p)` reads
/// guide-groom point `p`.
#[inline(always)]
pub fn from_guide(span: GuideSpan, i: u32, n: u32, rest_i: Vec3, at: &impl Fn(u32) -> GuidePoint) -> (Vec3, Vec3, f32) {
    let m = span.count;
    if m == n {
        // Point for point (most grooms give every strand the same count): `s = i`, and the
        // sums below at `u = 0` (or 1 at the tip) give exactly this.
        let (x, w, f, r) = at(span.first + i);
        return (x, rotate(f, rest_i - r), w);
    }
    let (j, u) = same_fraction(i, n, m);
    let (x0, w0, f0, r0) = at(span.first + j);
    let (x1, w1, f1, r1) = at(span.first + j + 1);
    let frame = if u > 0.0 { f1 } else { f0 };
    let offset = rotate(frame, rest_i - mix(r0, r1, u));
    (mix(x0, x1, u), offset, w0 * (1.0 - u) + w1 * u)
}

/// Point `i` of a follower of `n` points with rest position `rest_i`, following `f` over
/// guides `spans`: each guide's point plus its turned offset, shrunk by `clump` times that
/// guide's wetness, weighted by `f`'s weights with `clump` times the nearest guide's wetness
/// moved to the nearest guide (a wet follower closes on it: clumps). Returns the position and
/// the weighted wetness.
#[inline(always)]
pub fn follow_point(
    f: &Follow,
    spans: &[GuideSpan],
    i: u32,
    n: u32,
    rest_i: Vec3,
    clump: f32,
    at: &impl Fn(u32) -> GuidePoint,
) -> (Vec3, f32) {
    let (g0, d0, s0) = from_guide(spans[f.guides[0] as usize], i, n, rest_i, at);
    let shift = clump * s0;
    let w0 = f.weights[0] + shift * (1.0 - f.weights[0]);
    let mut x = (g0 + d0 * (1.0 - clump * s0)) * w0;
    let mut wet = s0 * w0;
    for k in 1..3 {
        if f.weights[k] == 0.0 {
            continue;
        }
        let (p, d, s) = from_guide(spans[f.guides[k] as usize], i, n, rest_i, at);
        let w = f.weights[k] * (1.0 - shift);
        x += (p + d * (1.0 - clump * s)) * w;
        wet += s * w;
    }
    (x, wet)
}

/// Point `i` of host strand `h` as the output shows it: following `fl.follow`, or, blending
/// by `a` < 1, `fl.from` moved toward that by `a`.
#[inline]
pub fn output_point(fl: &Followers, h: usize, i: u32, a: f32, at: &impl Fn(u32) -> GuidePoint) -> (Vec3, f32) {
    let first = fl.strand_first[h];
    let n = fl.strand_first[h + 1] - first;
    let rest_i = fl.rest[(first + i) as usize];
    let now = follow_point(&fl.follow[h], &fl.spans, i, n, rest_i, fl.clump, at);
    if a >= 1.0 || fl.from.is_empty() {
        return now;
    }
    let old = follow_point(&fl.from[h], &fl.spans, i, n, rest_i, fl.clump, at);
    (mix(old.0, now.0, a), old.1 * (1.0 - a) + now.1 * a)
}

/// The velocity of point `i` of a follower of `n` points: its guides' velocities at the same
/// fraction of their length, weighted as [`Follow::weights`] (what a guide that starts to be
/// simulated starts with). `vel(p)` reads guide-groom point `p`.
pub fn follow_velocity(f: &Follow, spans: &[GuideSpan], i: u32, n: u32, vel: &impl Fn(u32) -> Vec3) -> Vec3 {
    let mut v = Vec3::ZERO;
    for k in 0..3 {
        if f.weights[k] == 0.0 {
            continue;
        }
        let span = spans[f.guides[k] as usize];
        let (j, u) = same_fraction(i, n, span.count);
        v += mix(vel(span.first + j), vel(span.first + j + 1), u) * f.weights[k];
    }
    v
}

/// A head rotation as the law's xyzw quaternion.
pub fn head_quat(q: Quat) -> Vec4 {
    Vec4::from_array(q.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frame turns as glam's quaternions do.
    #[test]
    fn frames_compose_as_quaternions() {
        let a = Quat::from_rotation_z(0.7);
        let b = Quat::from_rotation_x(-0.3);
        let v = Vec3::new(0.2, -0.5, 0.9);
        let q = quat_mul(head_quat(a), head_quat(b));
        assert!((rotate(q, v) - (a * b) * v).length() < 1e-6);
    }

    /// A guide following itself gives its own points exactly; a follower offset from a straight
    /// guide keeps its offset as the guide swings, turned with it (its root with the head only).
    #[test]
    fn follow_point_is_exact_on_guides_and_turns_offsets() {
        let rest: Vec<Vec3> = (0..5)
            .map(|i| Vec3::new(0.0, -0.1 * i as f32, 0.0))
            .chain((0..5).map(|i| Vec3::new(0.01, -0.1 * i as f32, 0.0)))
            .collect();
        let span = GuideSpan {
            first: 0,
            rest: 0,
            count: 5,
            host: 0,
        };
        // The guide swung 90 degrees about z: it now points along +x.
        let x: Vec<Vec3> = (0..5).map(|i| Vec3::new(0.1 * i as f32, 0.0, 0.0)).collect();
        let head = head_quat(Quat::IDENTITY);
        let frames: Vec<Vec4> = (0..5)
            .map(|j| guide_frame_at(span, j, &rest, head, |p| x[p as usize]))
            .collect();
        let at = |p: u32| (x[p as usize], 0.0, frames[p as usize], rest[p as usize]);
        let own = Follow::own(0);
        for i in 0..5 {
            let (p, _) = follow_point(&own, &[span], i, 5, rest[i as usize], 0.8, &at);
            assert_eq!(p, x[i as usize], "the guide's own point {i}");
            let (q, _) = follow_point(&own, &[span], i, 5, rest[5 + i as usize], 0.8, &at);
            // Rest offset +x 1 cm from a guide along -y; turned by -y -> +x (a +90° turn about
            // z), +x goes to +y; at the root no segment arrives and the offset stays +x.
            let want = if i == 0 {
                Vec3::new(0.01, 0.0, 0.0)
            } else {
                Vec3::new(0.0, 0.01, 0.0)
            };
            assert!((q - (x[i as usize] + want)).length() < 1e-6, "{i}: {q}");
        }
    }

    /// A wet follower closes on its guide by `clump` times the wetness.
    #[test]
    fn wet_followers_clump() {
        let rest = [
            Vec3::ZERO,
            Vec3::new(0.0, -0.1, 0.0),
            Vec3::new(0.02, 0.0, 0.0),
            Vec3::new(0.02, -0.1, 0.0),
        ];
        let span = GuideSpan {
            first: 0,
            rest: 0,
            count: 2,
            host: 0,
        };
        let head = head_quat(Quat::IDENTITY);
        for wet in [0.0f32, 0.5, 1.0] {
            let at = |p: u32| (rest[p as usize], wet, head, rest[p as usize]);
            let (q, w) = follow_point(&Follow::own(0), &[span], 1, 2, rest[3], 0.8, &at);
            assert!((q.x - 0.02 * (1.0 - 0.8 * wet)).abs() < 1e-7, "wet {wet}: {q}");
            assert_eq!(w, wet);
        }
    }
}
