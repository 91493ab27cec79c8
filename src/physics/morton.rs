//! Morton (Z-curve) order of strand roots: the CPU layout groups neighbouring strands into
//! blocks by it, and the guides' spread order ([`super::followers::spread_order`]) is built on
//! it.

use glam::Vec3;

/// Strand indices sorted by the Morton code of their roots (10 bits per axis over the box
/// `lo`..`hi`, which holds them; ties in index order).
pub fn order(roots: &[Vec3], lo: Vec3, hi: Vec3) -> Vec<u32> {
    let scale = 1023.0 / (hi - lo).max(Vec3::splat(1e-12));
    let spread = |v: u32| -> u64 {
        let mut x = v as u64 & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    };
    let mut keyed: Vec<(u64, u32)> = roots
        .iter()
        .enumerate()
        .map(|(s, &p)| {
            let q = (p - lo) * scale;
            let key = spread(q.x as u32) | (spread(q.y as u32) << 1) | (spread(q.z as u32) << 2);
            (key, s as u32)
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, s)| s).collect()
}

/// The bounds of `points` (an empty set gives an inverted box).
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}
