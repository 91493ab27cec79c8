//! Roots follow the head: the head transform of each substep, interpolated from the previous
//! step's transform to this step's (scale and translation linearly, rotation by slerp), the
//! last substep landing exactly on the new transform. Both backends place pinned points and
//! colliders with these; fixed-step updates place each step's head the same way.

use glam::{Affine3A, Quat, Vec3};

/// The head transform a fraction `a` of the way from `from` to `to` (`a` = 1 gives `to`
/// exactly, 0 gives `from` exactly).
pub fn head_between(from: &Affine3A, to: &Affine3A, a: f32) -> Affine3A {
    if a >= 1.0 {
        return *to;
    }
    if a <= 0.0 {
        return *from;
    }
    HeadPath::new(from, to).at(a)
}

/// A transform's path over a step, its two ends taken apart once (scale, rotation,
/// translation), so that each substep's transform costs a lerp and a slerp: what a step's
/// substeps and a collider on its own frame need, with [`head_between`]'s bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadPath {
    from: Affine3A,
    to: Affine3A,
    parts: [(Vec3, Quat, Vec3); 2],
}

impl HeadPath {
    /// The path from `from` to `to`.
    pub fn new(from: &Affine3A, to: &Affine3A) -> Self {
        HeadPath {
            from: *from,
            to: *to,
            parts: [from.to_scale_rotation_translation(), to.to_scale_rotation_translation()],
        }
    }

    /// The transform a fraction `a` of the way ([`head_between`]).
    #[inline]
    pub fn at(&self, a: f32) -> Affine3A {
        if a >= 1.0 {
            return self.to;
        }
        if a <= 0.0 {
            return self.from;
        }
        let [(s0, r0, t0), (s1, r1, t1)] = self.parts;
        Affine3A::from_scale_rotation_translation(s0.lerp(s1, a), r0.slerp(r1, a), t0.lerp(t1, a))
    }
}

/// Fills `out` (one entry per substep) with the head transform at the end of each substep.
pub fn substep_heads_into(from: &Affine3A, to: &Affine3A, out: &mut [Affine3A]) {
    let n = out.len();
    let path = HeadPath::new(from, to);
    for (s, head) in out.iter_mut().enumerate() {
        *head = path.at((s + 1) as f32 / n as f32);
    }
}
