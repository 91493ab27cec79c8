//! The clumping measures. Dry strands spread out; wet strands gather into bundles, so both
//! drop. The tip measure is the mean distance (m) from each strand tip to the nearest other
//! tip; the along-strand measure averages the same at a strand's quarter points (a quarter,
//! half, three quarters of the way, and the tip), so bundles that form along long hair count
//! even where the tips still fan out.

use super::grid::Grid;
use glam::Vec3;

/// Mean nearest-other-tip distance over `tips`; 0 for fewer than two tips. Each tip's nearest
/// is exact (the brute-force minimum, so the same bits): a grid query around it that doubles
/// until what it found lies within the box's half-side.
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
    let mut grid = Grid::without_prefilter(n, cell);
    grid.build(tips);
    // Room for a query over every column, so no box is ever too wide.
    let mut runs = vec![(0u32, 0u32); (grid.dims().x * grid.dims().y) as usize];
    // A box of this half-side around any tip holds every tip.
    let whole = (hi - lo).length();
    let mut sum = 0.0f64;
    for (i, &p) in tips.iter().enumerate() {
        sum += (nearest_other_sq(&grid, tips, i, p, cell, whole, &mut runs) as f64).sqrt();
    }
    (sum / n as f64) as f32
}

/// The squared distance from `p` (tip `i`) to the nearest other tip. A box of half-side `r`
/// holds every tip within `r` of `p`, so once the nearest found is within `r` it is the
/// nearest of all; else `r` doubles, up to `whole`, where the box holds every tip. Doubling
/// keeps a lone tip's cost near that of its last box (the search over all tips it replaces
/// took seconds on a soaked 100,000-strand groom).
fn nearest_other_sq(grid: &Grid, pts: &[Vec3], i: usize, p: Vec3, r0: f32, whole: f32, runs: &mut [(u32, u32)]) -> f32 {
    let mut r = r0;
    // Positions are finite in a simulation; a bound on the rounds keeps a NaN from looping.
    for _ in 0..64 {
        let n = grid.runs_in_box(p - r, p + r, runs).expect("room for every column");
        let mut best = f32::INFINITY;
        for &(s, e) in &runs[..n] {
            for &j in &grid.sorted()[s as usize..e as usize] {
                if j as usize != i {
                    best = best.min((pts[j as usize] - p).length_squared());
                }
            }
        }
        if best <= r * r || r >= whole {
            return best;
        }
        r *= 2.0;
    }
    pts.iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, &q)| (q - p).length_squared())
        .fold(f32::INFINITY, f32::min)
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
    let levels = ALONG_STRAND_LEVELS.map(|level| mean_nearest_tip_distance(&level_points(points, strand_first, level)));
    mean_of_levels(&levels)
}

/// Each strand's point at `level` of its length, the points
/// [`mean_nearest_along_strands`] measures at that level.
pub fn level_points(points: &[Vec3], strand_first: &[u32], level: f32) -> Vec<Vec3> {
    strand_first
        .windows(2)
        .map(|w| {
            let n = (w[1] - w[0]) as f32;
            points[w[0] as usize + (level * (n - 1.0)).round() as usize]
        })
        .collect()
}

/// [`mean_nearest_along_strands`] from its levels' measures (in [`ALONG_STRAND_LEVELS`]'
/// order), summed in that order.
pub fn mean_of_levels(levels: &[f32; ALONG_STRAND_LEVELS.len()]) -> f32 {
    let sum = levels.iter().fold(0.0f64, |sum, &m| sum + m as f64);
    (sum / ALONG_STRAND_LEVELS.len() as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::Lcg;

    /// The brute-force measure: every tip against every other, summed in the same order.
    fn brute(tips: &[Vec3]) -> f32 {
        let sum: f64 = tips
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let best = tips
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, &q)| (q - p).length_squared())
                    .fold(f32::INFINITY, f32::min);
                (best as f64).sqrt()
            })
            .sum();
        (sum / tips.len() as f64) as f32
    }

    /// Tight bundles, lone tips far from everything, a flat sheet and coincident tips: the
    /// grid's doubling search gives brute force's bits on each.
    #[test]
    fn the_measure_equals_brute_force() {
        let mut rng = Lcg(7);
        let mut r = || rng.next_f32();
        let mut clouds: Vec<Vec<Vec3>> = Vec::new();
        // Bundles of 20 tips within 0.5 mm, 100 bundles over a 30 cm box, and 30 lone tips
        // up to a metre away.
        let mut c = Vec::new();
        for _ in 0..100 {
            let centre = Vec3::new(r(), r(), r()) * 0.3;
            for _ in 0..20 {
                c.push(centre + Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 5e-4);
            }
        }
        for _ in 0..30 {
            c.push(Vec3::new(r() - 0.5, r() * 2.0, r()) * 1.0);
        }
        clouds.push(c);
        // A flat sheet (tips on a surface) and a line (spacing far below the cell guess).
        clouds.push((0..1500).map(|_| Vec3::new(r(), 0.0, r()) * 0.2).collect());
        clouds.push((0..800).map(|k| Vec3::new(k as f32 * 1e-3, 0.1, 0.0)).collect());
        // Coincident tips and two tips alone.
        clouds.push(vec![Vec3::splat(0.25); 10]);
        clouds.push(vec![Vec3::ZERO, Vec3::new(3.0, -2.0, 1.0)]);
        for (k, tips) in clouds.iter().enumerate() {
            let (got, want) = (mean_nearest_tip_distance(tips), brute(tips));
            assert_eq!(got.to_bits(), want.to_bits(), "cloud {k}: {got} against {want}");
        }
    }
}
