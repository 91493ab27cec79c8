//! Roots follow the head: the head transform of each substep, interpolated from the previous
//! step's transform to this step's (scale and translation linearly, rotation by slerp), the
//! last substep landing exactly on the new transform. Both backends place pinned points and
//! colliders with these.

use glam::Affine3A;

/// Fills `out` (one entry per substep) with the head transform at the end of each substep.
pub fn substep_heads_into(from: &Affine3A, to: &Affine3A, out: &mut [Affine3A]) {
    let n = out.len();
    let (s0, r0, t0) = from.to_scale_rotation_translation();
    let (s1, r1, t1) = to.to_scale_rotation_translation();
    for (s, head) in out.iter_mut().enumerate() {
        let a = (s + 1) as f32 / n as f32;
        *head = if s + 1 == n {
            *to
        } else {
            Affine3A::from_scale_rotation_translation(s0.lerp(s1, a), r0.slerp(r1, a), t0.lerp(t1, a))
        };
    }
}
