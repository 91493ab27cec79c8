//! Guides and followers (docs/GUIDES.md): which strands are guides and in what order a lower
//! simulated fraction keeps them ([`spread_order`], [`choose`]), which guides each strand
//! follows ([`bind`]), and what a backend needs to write them ([`Followers`]). Where a
//! follower's points are is the law in [`super::follow`].

use glam::Vec3;

/// How one host strand follows: up to three guide strands (guide-groom order) and their
/// weights (summing to 1; an unused slot repeats the first guide with weight 0). A simulated
/// guide follows itself with weight 1 and a zero offset, which gives its own points exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Follow {
    /// Guide strands, nearest first.
    pub guides: [u32; 3],
    /// Their weights.
    pub weights: [f32; 3],
}

impl Follow {
    /// Guide `g` alone (a simulated guide following itself).
    pub fn own(g: u32) -> Follow {
        Follow {
            guides: [g; 3],
            weights: [1.0, 0.0, 0.0],
        }
    }
}

/// Where a guide's points are: its first point in the simulated (guide) groom, its first point
/// in the host's groom (its rest pose), and its point count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GuideSpan {
    /// First point in the guide groom (the backend's state).
    pub first: u32,
    /// First point in the host's groom (the rest positions).
    pub rest: u32,
    /// Points.
    pub count: u32,
    /// Its host strand (with skinned roots, the guide's frames start from that strand's root
    /// frame instead of the head's rotation).
    pub host: u32,
}

/// What a backend needs to write every host strand from the guides: the host's rest pose, the
/// guides' spans, each host strand's binding, and the binding the output blends from while a
/// change of the simulated fraction settles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Followers {
    /// Host point offsets per strand (strands + 1).
    pub strand_first: Vec<u32>,
    /// The host's rest pose, head space.
    pub rest: Vec<Vec3>,
    /// Per guide (guide-groom order).
    pub spans: Vec<GuideSpan>,
    /// Per host strand: the guides it follows now.
    pub follow: Vec<Follow>,
    /// Per host strand: the guides it followed before the last change of the simulated
    /// fraction (the output moves from these to `follow` by the blend); empty when settled.
    pub from: Vec<Follow>,
    /// [`crate::params::Guides::clump`].
    pub clump: f32,
    /// Skinned roots only (else empty): per host strand, its root points (the root and the
    /// points pinned after it, 0 when the root is free), which the output places on the
    /// strand's own root frame (`follow::OwnRoot`).
    pub root_points: Vec<u32>,
}

/// The strands of `roots` in spread order: Morton order of the roots taken in bit-reversed
/// index order, so that every prefix is an even subsample of the scalp (the first quarter
/// takes about every fourth strand along the Z-curve).
pub fn spread_order(roots: &[Vec3]) -> Vec<u32> {
    let (lo, hi) = super::morton::bounds(roots);
    let z = super::morton::order(roots, lo, hi);
    let n = z.len();
    if n <= 1 {
        return z;
    }
    let bits = usize::BITS - (n - 1).leading_zeros();
    (0..1usize << bits)
        .map(|j| j.reverse_bits() >> (usize::BITS - bits))
        .filter(|&r| r < n)
        .map(|r| z[r])
        .collect()
}

/// The guides of a groom with roots `roots`, in spread order: the strands `is_guide` keeps
/// ([`crate::params::GuideChoice`]), or the first `count` when `count` is given.
pub fn choose(roots: &[Vec3], is_guide: impl Fn(u32) -> bool, count: Option<usize>) -> Vec<u32> {
    let mut g: Vec<u32> = spread_order(roots).into_iter().filter(|&s| is_guide(s)).collect();
    if let Some(c) = count {
        g.truncate(c.max(1));
    }
    g
}

/// Lloyd iterations of [`cluster`]: the seeds are already even, and the cost after this many
/// barely moves (each is a nearest-centre query per root).
pub const CLUSTER_ITERATIONS: usize = 8;

/// `k` guides chosen by clustering the roots (k-means, [`CLUSTER_ITERATIONS`] Lloyd
/// iterations seeded by the first `k` of the spread order; sums in f64 in strand order, so
/// deterministic), each cluster's guide the strand nearest its centre (ties by index).
/// Returns host strand indices, ascending; fewer than `k` only where a cluster ends empty.
/// Clusters follow the roots' density, so followers sit nearer their guides where the scalp is
/// uneven than with the spread choice.
pub fn cluster(roots: &[Vec3], k: usize) -> Vec<u32> {
    let k = k.clamp(1, roots.len().max(1));
    let mut centres: Vec<Vec3> = choose(roots, |_| true, Some(k))
        .iter()
        .map(|&s| roots[s as usize])
        .collect();
    let mut near = Vec::with_capacity(1);
    let mut member = vec![0u32; roots.len()];
    for it in 0..=CLUSTER_ITERATIONS {
        let grid = RootGrid::new(&centres);
        for (s, &r) in roots.iter().enumerate() {
            grid.nearest(r, 1, &mut near);
            member[s] = near[0].1;
        }
        if it == CLUSTER_ITERATIONS {
            break;
        }
        let mut sum = vec![(glam::DVec3::ZERO, 0u32); centres.len()];
        for (s, &c) in member.iter().enumerate() {
            sum[c as usize].0 += roots[s].as_dvec3();
            sum[c as usize].1 += 1;
        }
        for (c, (total, n)) in centres.iter_mut().zip(sum) {
            if n > 0 {
                *c = (total / n as f64).as_vec3();
            }
        }
    }
    let mut best: Vec<Option<(f32, u32)>> = vec![None; centres.len()];
    for (s, &c) in member.iter().enumerate() {
        let d2 = roots[s].distance_squared(centres[c as usize]);
        let b = &mut best[c as usize];
        if b.is_none_or(|(d, _)| d2 < d) {
            *b = Some((d2, s as u32));
        }
    }
    let mut picked: Vec<u32> = best.into_iter().flatten().map(|(_, s)| s).collect();
    picked.sort_unstable();
    picked
}

/// Which guides each host strand follows when the guides `active` (host strand indices, the
/// guide groom's first strands) are simulated: an active guide follows itself; any other
/// strand the `per` (1 or 3) active guides with the nearest roots, weighted by inverse root
/// distance (ties by index). Deterministic; a dense grid over the guides' roots keeps it
/// O(strands).
pub fn bind(roots: &[Vec3], active: &[u32], per: u32) -> Vec<Follow> {
    let mut guide_of = vec![u32::MAX; roots.len()];
    for (g, &s) in active.iter().enumerate() {
        guide_of[s as usize] = g as u32;
    }
    let g_roots: Vec<Vec3> = active.iter().map(|&s| roots[s as usize]).collect();
    let grid = RootGrid::new(&g_roots);
    let per = (per as usize).clamp(1, 3).min(active.len());
    let mut near = Vec::with_capacity(8);
    roots
        .iter()
        .enumerate()
        .map(|(s, &r)| {
            if guide_of[s] != u32::MAX {
                return Follow::own(guide_of[s]);
            }
            grid.nearest(r, per, &mut near);
            let mut f = Follow::own(near[0].1);
            let inv: Vec<f32> = near.iter().map(|&(d2, _)| 1.0 / (d2.sqrt() + ROOT_EPS)).collect();
            let total: f32 = inv.iter().sum();
            for (k, &(_, g)) in near.iter().enumerate() {
                f.guides[k] = g;
                f.weights[k] = inv[k] / total;
            }
            f
        })
        .collect()
}

/// Added to root distances before inverting them, m: a follower whose root sits on a guide's
/// takes that guide's weight (almost) whole.
const ROOT_EPS: f32 = 1e-6;

/// A dense grid over guide roots for nearest-neighbour queries.
struct RootGrid<'a> {
    roots: &'a [Vec3],
    lo: Vec3,
    cell: f32,
    dims: [i64; 3],
    /// Counting sort of the roots by cell: cell `c` holds `items[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> RootGrid<'a> {
    fn new(roots: &'a [Vec3]) -> Self {
        let (lo, hi) = super::morton::bounds(roots);
        let ext = (hi - lo).max(Vec3::splat(1e-6));
        let n = roots.len().max(1) as f32;
        // Roots lie on a surface: about one guide per cell across it, but no more than a few
        // cells per guide in all.
        let cell = (ext.max_element() / n.sqrt()).max((ext.x * ext.y * ext.z / (4.0 * n)).cbrt());
        let dims = [0, 1, 2].map(|a| (ext[a] / cell) as i64 + 1);
        let cells = (dims[0] * dims[1] * dims[2]) as usize;
        let mut start = vec![0u32; cells + 1];
        let cell_of: Vec<usize> = roots
            .iter()
            .map(|&p| {
                let c = Self::coord(lo, cell, p);
                let c = [0, 1, 2].map(|a| c[a].clamp(0, dims[a] - 1));
                (c[0] + dims[0] * (c[1] + dims[1] * c[2])) as usize
            })
            .collect();
        for &c in &cell_of {
            start[c + 1] += 1;
        }
        for c in 0..cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; roots.len()];
        for (i, &c) in cell_of.iter().enumerate() {
            items[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        RootGrid {
            roots,
            lo,
            cell,
            dims,
            start,
            items,
        }
    }

    fn coord(lo: Vec3, cell: f32, p: Vec3) -> [i64; 3] {
        let q = (p - lo) / cell;
        [q.x.floor() as i64, q.y.floor() as i64, q.z.floor() as i64]
    }

    /// The `k` roots nearest `p` into `out` as (squared distance, index), nearest first (ties
    /// by index). Rings of cells around `p`'s cell are visited until no unvisited root can be
    /// nearer than the k-th found: after ring `r`, every unvisited root is at least `r` cells
    /// away along some axis.
    fn nearest(&self, p: Vec3, k: usize, out: &mut Vec<(f32, u32)>) {
        out.clear();
        let c = Self::coord(self.lo, self.cell, p);
        let reach = (0..3)
            .map(|a| c[a].abs().max((c[a] - self.dims[a] + 1).abs()))
            .max()
            .unwrap_or(0);
        for r in 0..=reach {
            for z in c[2] - r..=c[2] + r {
                for y in c[1] - r..=c[1] + r {
                    for x in c[0] - r..=c[0] + r {
                        let ring = (x - c[0]).abs().max((y - c[1]).abs()).max((z - c[2]).abs());
                        let inside =
                            x >= 0 && y >= 0 && z >= 0 && x < self.dims[0] && y < self.dims[1] && z < self.dims[2];
                        if ring != r || !inside {
                            continue;
                        }
                        let cell = (x + self.dims[0] * (y + self.dims[1] * z)) as usize;
                        for &i in &self.items[self.start[cell] as usize..self.start[cell + 1] as usize] {
                            out.push((p.distance_squared(self.roots[i as usize]), i));
                        }
                    }
                }
            }
            if out.len() >= k {
                out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                out.truncate(k);
                let safe = r as f32 * self.cell;
                if out[k - 1].0 <= safe * safe {
                    return;
                }
            }
        }
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out.truncate(k);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every prefix of the spread order is spread: the first quarter of a 64 × 64 sheet of
    /// roots leaves no root farther than 3 spacings from one of its own.
    /// Clustering picks `k` distinct strands, the same ones every run, and on an uneven scalp
    /// (a dense patch beside a sparse one) its followers sit nearer their guides than with the
    /// spread choice: the mean distance from a root to its nearest guide root is lower.
    #[test]
    fn clusters_fit_an_uneven_scalp_better_than_spread() {
        let mut roots = Vec::new();
        let mut rng = crate::scenes::Lcg(21);
        for _ in 0..3000 {
            roots.push(Vec3::new(rng.next_f32() * 0.05, rng.next_f32() * 0.05, 0.0));
        }
        for _ in 0..1000 {
            roots.push(Vec3::new(0.05 + rng.next_f32() * 0.15, rng.next_f32() * 0.05, 0.0));
        }
        let k = 100;
        let picked = cluster(&roots, k);
        assert_eq!(picked, cluster(&roots, k), "deterministic");
        assert!(picked.len() <= k && picked.len() >= k - 2, "{} guides", picked.len());
        assert!(picked.windows(2).all(|w| w[0] < w[1]), "distinct, ascending");
        let mean_to_nearest = |guides: &[u32]| {
            let g: Vec<Vec3> = guides.iter().map(|&s| roots[s as usize]).collect();
            let grid = RootGrid::new(&g);
            let mut near = Vec::new();
            roots
                .iter()
                .map(|&r| {
                    grid.nearest(r, 1, &mut near);
                    near[0].0.sqrt() as f64
                })
                .sum::<f64>()
                / roots.len() as f64
        };
        let spread = choose(&roots, |_| true, Some(k));
        let (c, s) = (mean_to_nearest(&picked), mean_to_nearest(&spread));
        assert!(c < 0.95 * s, "cluster {c:.5} m against spread {s:.5} m");
    }

    #[test]
    fn spread_prefixes_cover_the_scalp() {
        let roots: Vec<Vec3> = (0..64 * 64)
            .map(|k| Vec3::new((k % 64) as f32, (k / 64) as f32, 0.0))
            .collect();
        let order = spread_order(&roots);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..64 * 64).collect::<Vec<u32>>(), "a permutation");
        for frac in [4, 10, 50] {
            let first: Vec<u32> = order[..roots.len() / frac].to_vec();
            let b = bind(&roots, &first, 1);
            let worst = roots
                .iter()
                .zip(&b)
                .map(|(r, f)| r.distance(roots[first[f.guides[0] as usize] as usize]))
                .fold(0.0f32, f32::max);
            let spacing = (frac as f32).sqrt();
            assert!(
                worst <= 2.5 * spacing,
                "1/{frac}: a root {worst} from its guide (spacing {spacing})"
            );
        }
    }

    /// The grid's nearest guides equal brute force's, distances and ties by index.
    #[test]
    fn nearest_guides_equal_brute_force() {
        let mut rng = crate::scenes::Lcg(5);
        let roots: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), 0.3 * rng.next_f32()))
            .collect();
        let active: Vec<u32> = (0..3000).step_by(7).collect();
        let b = bind(&roots, &active, 3);
        for (s, f) in b.iter().enumerate() {
            if s % 7 == 0 {
                assert_eq!(*f, Follow::own((s / 7) as u32));
                continue;
            }
            let mut all: Vec<(f32, u32)> = active
                .iter()
                .enumerate()
                .map(|(g, &h)| (roots[s].distance_squared(roots[h as usize]), g as u32))
                .collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let want: Vec<u32> = all[..3].iter().map(|x| x.1).collect();
            assert_eq!(f.guides.to_vec(), want, "strand {s}");
            assert!((f.weights.iter().sum::<f32>() - 1.0).abs() < 1e-6);
            assert!(f.weights[0] >= f.weights[1] && f.weights[1] >= f.weights[2]);
        }
    }
}
