//! Roots on a skinned mesh: each strand's pinned points follow a root frame the host sets each
//! step (a position and a rotation, in the world) instead of the head transform. A pinned point
//! whose rest position (head space) is `r`, on a strand whose first point rests at `r0`, goes to
//! `position + rotation (r - r0)`: the root itself lands exactly on `position`, and the points
//! pinned after it (TressFX pins two) keep their rest offset turned with the frame. Over a step's
//! substeps a frame moves as the head does (position linearly, rotation by slerp, the last
//! substep landing exactly on the new frame).
//!
//! A root that moves more than the teleport distance in one step (a cut, a respawn) does not
//! sweep its strand across the world: the whole strand is carried rigidly from the old frame to
//! the new one before the step, its velocities set to zero, and its pinned points start the
//! step on the new frame. Both backends run these functions (`roots.wgsl` mirrors them).

use glam::{Quat, Vec3};

/// The default teleport distance, m: a root moving this far in one step moves at 30 m/s at
/// 60 Hz and 15 m/s at 30 Hz, beyond any animation of a body, yet a cut across a room trips it.
pub const TELEPORT_DISTANCE: f32 = 0.5;

/// Where one strand's root is and how it is turned, in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct RootFrame {
    /// The strand's first point, m.
    pub position: Vec3,
    /// The turn from the groom's rest frame (head space) to the world; unit length.
    pub rotation: Quat,
}

impl RootFrame {
    /// The frame of a root resting at `r0` under no motion.
    pub fn at_rest(r0: Vec3) -> RootFrame {
        RootFrame {
            position: r0,
            rotation: Quat::IDENTITY,
        }
    }

    /// Where a point pinned at `offset` from the root (its rest position minus the root's)
    /// goes.
    #[inline]
    pub fn place(&self, offset: Vec3) -> Vec3 {
        self.position + self.rotation * offset
    }

    /// Carries a point of the strand rigidly from this frame to `to` (a teleport).
    #[inline]
    pub fn carry(&self, to: &RootFrame, x: Vec3) -> Vec3 {
        to.position + (to.rotation * self.rotation.conjugate()) * (x - self.position)
    }
}

/// The frame a fraction `a` of the way from `from` to `to` (1 gives `to` exactly, 0 `from`).
#[inline]
pub fn root_between(from: &RootFrame, to: &RootFrame, a: f32) -> RootFrame {
    if a >= 1.0 {
        return *to;
    }
    if a <= 0.0 {
        return *from;
    }
    RootFrame {
        position: from.position.lerp(to.position, a),
        rotation: slerp(from.rotation, to.rotation, a),
    }
}

/// Spherical interpolation along the shorter arc, written out so that `roots.wgsl` computes
/// the same expression (near-equal rotations fall back to a normalized lerp).
#[inline]
pub fn slerp(p: Quat, q: Quat, a: f32) -> Quat {
    let mut d = p.dot(q);
    let mut q = q;
    if d < 0.0 {
        d = -d;
        q = -q;
    }
    if d > 0.9995 {
        return (p * (1.0 - a) + q * a).normalize();
    }
    let theta = d.acos();
    let s = theta.sin();
    let wp = ((1.0 - a) * theta).sin() / s;
    let wq = (a * theta).sin() / s;
    (p * wp + q * wq).normalize()
}

/// Whether a root moving from `from` to `to` in one step teleports under `distance` (0: never).
#[inline]
pub fn teleports(from: &RootFrame, to: &RootFrame, distance: f32) -> bool {
    distance > 0.0 && from.position.distance(to.position) > distance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_are_exact_and_the_middle_turns_half_way() {
        let a = RootFrame {
            position: Vec3::new(0.1, 0.2, 0.3),
            rotation: Quat::from_rotation_z(0.2),
        };
        let b = RootFrame {
            position: Vec3::new(-0.1, 0.0, 0.5),
            rotation: Quat::from_rotation_z(1.0),
        };
        assert_eq!(root_between(&a, &b, 1.0), b);
        assert_eq!(root_between(&a, &b, 0.0), a);
        let m = root_between(&a, &b, 0.5);
        assert!((m.position - Vec3::new(0.0, 0.1, 0.4)).length() < 1e-6);
        assert!(m.rotation.angle_between(Quat::from_rotation_z(0.6)) < 1e-5);
        // Against glam's own slerp, far and near.
        for (p, q) in [
            (a.rotation, b.rotation),
            (Quat::from_rotation_x(0.1), Quat::from_rotation_x(0.1001)),
        ] {
            for k in 0..=8 {
                let t = k as f32 / 8.0;
                // Componentwise (an angle between near-equal rotations is all rounding).
                let (a, b) = (slerp(p, q, t), p.slerp(q, t));
                let d = (a - b).length().min((a + b).length());
                assert!(d < 1e-5, "{t}: {a:?} against glam's {b:?}");
            }
        }
    }

    #[test]
    fn a_carried_strand_keeps_its_shape_and_lands_on_the_new_root() {
        let from = RootFrame {
            position: Vec3::new(0.0, 0.0, 1.0),
            rotation: Quat::from_rotation_y(0.3),
        };
        let to = RootFrame {
            position: Vec3::new(5.0, -2.0, 1.0),
            rotation: Quat::from_rotation_x(-1.2),
        };
        let pts = [
            from.position,
            from.position + Vec3::new(0.0, 0.0, -0.1),
            Vec3::new(0.2, 0.1, 0.7),
        ];
        let moved: Vec<Vec3> = pts.iter().map(|p| from.carry(&to, *p)).collect();
        assert!((moved[0] - to.position).length() < 1e-6);
        for i in 0..3 {
            for j in 0..3 {
                let (d0, d1) = ((pts[i] - pts[j]).length(), (moved[i] - moved[j]).length());
                assert!((d0 - d1).abs() < 1e-5);
            }
        }
        assert!(teleports(&from, &to, 1.0) && !teleports(&from, &to, 0.0) && !teleports(&from, &to, 10.0));
    }
}
