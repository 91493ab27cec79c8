//! Followers on skinned roots (docs/GUIDES.md): a follower interpolated from its guides has
//! its root where the guides' roots and frames put it, which on a stretching or sliding skin
//! is not where its own root is. Its root points (the root and the points pinned after it) go
//! exactly where its own frame puts them, as a simulated strand's do (`RootFrame::place`); the
//! free points are moved by the shift that lands the last root point there, times `u²` where
//! `u` falls linearly from 1 at the last root point to 0 at the tip, so the strand leaves its
//! own root and ends, smoothly, where its guides say. (On a stretching, waving sheet against
//! every strand simulated, the square's mean error was below a linear fade's, a constant
//! shift's and no shift's: tests/guide_roots.rs, docs/GUIDES.md.)
//!
//! The CPU's output (`cpu/follower_output.rs`), the seeding of new guides (`sim/guides.rs`)
//! and `write_followers.wgsl` (`own_root_shift`, `own_root_point`) compute it.

use super::roots::RootFrame;
use glam::Vec3;

/// A host strand's own root as the follower output reads it.
#[derive(Clone, Copy, Debug)]
pub struct OwnRoot {
    /// Its frame now.
    pub frame: RootFrame,
    /// Its first point at rest (head space).
    pub rest_root: Vec3,
    /// Its root points: the root and the points pinned after it (0: a free root, which
    /// follows its guides alone).
    pub points: u32,
}

impl OwnRoot {
    /// Where rest point `rest_i` of the strand goes on its frame.
    #[inline]
    pub fn place(&self, rest_i: Vec3) -> Vec3 {
        self.frame.place(rest_i - self.rest_root)
    }

    /// The shift that moves the law's last root point `law_last` (rest `rest_last`) onto the
    /// frame.
    #[inline]
    pub fn shift(&self, rest_last: Vec3, law_last: Vec3) -> Vec3 {
        self.place(rest_last) - law_last
    }

    /// Point `i` of `n` (rest `rest_i`, where the guides put it `law_i`): a root point on the
    /// frame, a free point moved by `shift` times `u²`, `u = (n - 1 - i) / (n - k)` for `k`
    /// root points (1 at the last root point, 0 at the tip).
    #[inline]
    pub fn point(&self, i: u32, n: u32, rest_i: Vec3, law_i: Vec3, shift: Vec3) -> Vec3 {
        let k = self.points;
        if k == 0 {
            return law_i;
        }
        if i < k {
            return self.place(rest_i);
        }
        let u = (n - 1 - i) as f32 / (n - k) as f32;
        law_i + shift * (u * u)
    }
}

/// A strand's points as [`root_strand`] reads and moves them in place.
pub trait StrandPositions {
    /// Point `i`.
    fn get(&self, i: u32) -> Vec3;
    /// Moves point `i` to `x`.
    fn set(&mut self, i: u32, x: Vec3);
}

impl StrandPositions for [Vec3] {
    #[inline]
    fn get(&self, i: u32) -> Vec3 {
        self[i as usize]
    }
    #[inline]
    fn set(&mut self, i: u32, x: Vec3) {
        self[i as usize] = x;
    }
}

/// A strand of `n` points (rest `rest(i)`, where the guides put them in `x`) moved onto its
/// own root, in place.
#[inline]
pub fn root_strand(own: &OwnRoot, n: u32, rest: impl Fn(u32) -> Vec3, x: &mut (impl StrandPositions + ?Sized)) {
    let k = own.points.min(n);
    if k == 0 {
        return;
    }
    let shift = own.shift(rest(k - 1), x.get(k - 1));
    for i in 0..n {
        let moved = own.point(i, n, rest(i), x.get(i), shift);
        x.set(i, moved);
    }
}

/// A strand's root points: how many of its first points are pinned (`pinned` is its per-point
/// flags).
pub fn root_points(pinned: &[bool]) -> u32 {
    pinned.iter().take_while(|&&p| p).count() as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    /// Root points land on the frame exactly, the shift fades as the square to the tip, and a free
    /// root leaves the law's points alone.
    #[test]
    fn root_points_land_on_the_frame_and_the_shift_fades() {
        let rest: Vec<Vec3> = (0..5).map(|i| Vec3::new(0.0, -0.1 * i as f32, 0.0)).collect();
        let law: Vec<Vec3> = rest.iter().map(|r| *r + Vec3::new(0.3, 0.0, 0.0)).collect();
        let own = OwnRoot {
            frame: RootFrame {
                position: Vec3::new(1.0, 2.0, 3.0),
                rotation: Quat::from_rotation_z(0.5),
            },
            rest_root: rest[0],
            points: 2,
        };
        let mut out = law.clone();
        root_strand(&own, 5, |i| rest[i as usize], &mut out[..]);
        for i in 0..2 {
            assert_eq!(out[i], own.frame.place(rest[i] - rest[0]), "root point {i}");
        }
        let shift = out[1] - law[1];
        for i in 2..5 {
            let u = (4 - i) as f32 / 3.0;
            let want = law[i] + shift * (u * u);
            assert!((out[i] - want).length() < 1e-6, "point {i}: {} against {want}", out[i]);
        }
        assert_eq!(out[4], law[4], "the tip is the law's");
        let free = OwnRoot { points: 0, ..own };
        let mut same = law.clone();
        root_strand(&free, 5, |i| rest[i as usize], &mut same[..]);
        assert_eq!(same, law);
        assert_eq!(root_points(&[true, true, false, true]), 2);
        assert_eq!(root_points(&[false, true]), 0);
    }
}
