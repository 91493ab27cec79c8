//! The clumping measures. Dry strands spread out; wet strands gather into bundles, so both
//! drop. The tip measure is the mean distance (m) from each strand tip to the nearest other
//! tip; the along-strand measure averages the same at a strand's quarter points (a quarter,
//! half, three quarters of the way, and the tip), so bundles that form along long hair count
//! even where the tips still fan out.

use super::grid::Grid;
use glam::Vec3;

/// Mean nearest-other-tip distance over `tips`; 0 for fewer than two tips.
pub fn mean_nearest_tip_distance(tips: &[Vec3]) -> f32 {
    let n = tips.len();
    if n < 2 {
        return 0.0;
    }
    let (lo, hi) = tips
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)));
    // Tips lie on a surface: spacing ~ extent / sqrt(n); two spacings per cell finds most
    // nearest neighbours within one query.
    let cell = ((hi - lo).max_element() / (n as f32).sqrt() * 2.0).max(1e-6);
    let mut grid = Grid::new(n, cell);
    grid.build(tips);
    let mut sum = 0.0f64;
    for (i, &p) in tips.iter().enumerate() {
        let mut best = f32::INFINITY;
        grid.for_each_candidate(p, cell, |j| {
            if j as usize != i {
                best = best.min((tips[j as usize] - p).length_squared());
            }
        });
        if best > cell * cell {
            // Nothing certain within one cell: an isolated tip, search them all.
            best = tips
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &q)| (q - p).length_squared())
                .fold(f32::INFINITY, f32::min);
        }
        sum += (best as f64).sqrt();
    }
    (sum / n as f64) as f32
}

/// The quarter points where [`mean_nearest_along_strands`] measures, as fractions of a strand's
/// points (the root is pinned and never moves).
pub const ALONG_STRAND_LEVELS: [f32; 4] = [0.25, 0.5, 0.75, 1.0];

/// Mean over [`ALONG_STRAND_LEVELS`] of the mean nearest-other-strand distance at that level:
/// the point `round(level (n - 1))` of each strand of `n` points (strand `s` is
/// `strand_first[s]..strand_first[s + 1]` of `points`).
pub fn mean_nearest_along_strands(points: &[Vec3], strand_first: &[u32]) -> f32 {
    if points.is_empty() || strand_first.len() < 2 {
        return 0.0;
    }
    let mut level_points = Vec::with_capacity(strand_first.len() - 1);
    let mut sum = 0.0f64;
    for level in ALONG_STRAND_LEVELS {
        level_points.clear();
        level_points.extend(strand_first.windows(2).map(|w| {
            let n = (w[1] - w[0]) as f32;
            points[w[0] as usize + (level * (n - 1.0)).round() as usize]
        }));
        sum += mean_nearest_tip_distance(&level_points) as f64;
    }
    (sum / ALONG_STRAND_LEVELS.len() as f64) as f32
}
