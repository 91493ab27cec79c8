//! The clumping measure: the mean distance (m) from each strand tip to the nearest other tip.
//! Dry strands spread out; wet strands gather into bundles, so the measure drops.

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
