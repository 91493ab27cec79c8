//! Roots follow the head: the head transform of each substep, interpolated from the previous
//! step's transform to this step's (scale and translation linearly, rotation by slerp), the
//! last substep landing exactly on the new transform. Both backends place pinned points and
//! colliders with these; fixed-step updates place each step's head the same way.

use glam::Affine3A;

/// The head transform a fraction `a` of the way from `from` to `to` (`a` = 1 gives `to`
/// exactly, 0 gives `from` exactly).
pub fn head_between(from: &Affine3A, to: &Affine3A, a: f32) -> Affine3A {
    if a >= 1.0 {
        return *to;
    }
    if a <= 0.0 {
        return *from;
    }
    let (s0, r0, t0) = from.to_scale_rotation_translation();
    let (s1, r1, t1) = to.to_scale_rotation_translation();
    Affine3A::from_scale_rotation_translation(s0.lerp(s1, a), r0.slerp(r1, a), t0.lerp(t1, a))
}

/// Fills `out` (one entry per substep) with the head transform at the end of each substep.
pub fn substep_heads_into(from: &Affine3A, to: &Affine3A, out: &mut [Affine3A]) {
    let n = out.len();
    for (s, head) in out.iter_mut().enumerate() {
        *head = head_between(from, to, (s + 1) as f32 / n as f32);
    }
}
