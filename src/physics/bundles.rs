//! What a guide's water stands for (docs/GUIDES.md "Water"): with a fraction of the strands
//! simulated, each guide holds the water of its *bundle*, the hair of the host strands bound to
//! it, so a soaked groom holds the same water with a tenth of its strands simulated as with all
//! of them. A guide's capacity and hold limit are its bundle's; its own inertia takes its
//! share of the water (`wet::quantum_per_strand`).
//!
//! When the simulated fraction changes, the bundles change, and the water moves with the hair
//! it belongs to: guides that a higher fraction adds take their share of the water of the
//! guides they followed, and guides that a lower fraction drops give theirs to the guides they
//! now follow. Every move is a whole number of quanta taken from one point and given to
//! another, so the ledger stays exact.

use super::follow::same_fraction;
use super::followers::{Follow, GuideSpan};

/// Each guide's bundle under the bindings `follow` (one per host strand): `Σ_s w_s M_s / M_g`
/// over the host strands `s` bound to guide `g` with weight `w_s`, `M` a strand's dry mass, so
/// the bundles' hair is the groom's. A guide no strand follows (not simulated at this
/// fraction) stands for itself. Summed in f64 in host order: the same bits every time.
pub fn bundles(follow: &[Follow], strand_mass: &[f32], host_of: &[u32]) -> Vec<f32> {
    let mut sum = vec![0.0f64; host_of.len()];
    for (s, f) in follow.iter().enumerate() {
        for (&g, &w) in f.guides.iter().zip(&f.weights) {
            if w > 0.0 {
                sum[g as usize] += w as f64 * strand_mass[s] as f64;
            }
        }
    }
    sum.iter()
        .zip(host_of)
        .map(|(&m, &h)| match m > 0.0 {
            true => (m / strand_mass[h as usize] as f64) as f32,
            false => 1.0,
        })
        .collect()
}

/// The point of a strand of `m` points nearest point `j` of a strand of `n` points at the same
/// fraction of length (as the followers read their guides, [`same_fraction`]).
fn same_place(j: u32, n: u32, m: u32) -> u32 {
    if n == m {
        return j;
    }
    let (k, u) = same_fraction(j, n, m);
    k + (u >= 0.5) as u32
}

/// Moves `q` quanta (at most what `from` holds and what `to` has room for) from point `from`
/// to point `to`.
fn move_quanta(water: &mut [u32], from: usize, to: usize, q: u32) {
    let q = q.min(water[from]).min(u32::MAX - water[to]);
    water[from] -= q;
    water[to] += q;
}

/// The guides `added` start to be simulated (a higher fraction): each takes, point by point,
/// its share of each guide it followed (`before`, per host strand): `w M_e / (B_g M_g)` of
/// that guide's water at the same fraction of length, `B_g` the guide's bundle before.
/// `water` is every guide point's, in the guide groom's order; `spans` and `host_of` describe
/// the guides, `strand_mass` the host strands.
pub fn take_shares(
    water: &mut [u32],
    added: std::ops::Range<usize>,
    before: &[Follow],
    bundle_before: &[f32],
    spans: &[GuideSpan],
    host_of: &[u32],
    strand_mass: &[f32],
) {
    let start = water.to_vec();
    for e in added {
        let (h, to) = (host_of[e] as usize, spans[e]);
        let f = &before[h];
        for (&g, &w) in f.guides.iter().zip(&f.weights) {
            let g = g as usize;
            if w <= 0.0 || g == e {
                continue;
            }
            let share =
                w as f64 * strand_mass[h] as f64 / (bundle_before[g] as f64 * strand_mass[host_of[g] as usize] as f64);
            let from = spans[g];
            for j in 0..to.count {
                let src = (from.first + same_place(j, to.count, from.count)) as usize;
                let q = (start[src] as f64 * share.min(1.0)).floor() as u32;
                move_quanta(water, src, (to.first + j) as usize, q);
            }
        }
    }
}

/// The guides `dropped` stop being simulated (a lower fraction): each gives all its water,
/// point by point, to the guides it now follows (`follow`, per host strand) by their weights,
/// the remainder of the rounding to the nearest. Arguments as for [`take_shares`].
pub fn give_back(
    water: &mut [u32],
    dropped: std::ops::Range<usize>,
    follow: &[Follow],
    spans: &[GuideSpan],
    host_of: &[u32],
) {
    for d in dropped {
        let (f, from) = (&follow[host_of[d] as usize], spans[d]);
        for j in 0..from.count {
            let src = (from.first + j) as usize;
            let q = water[src];
            for k in (0..3).rev() {
                let (g, w) = (f.guides[k] as usize, f.weights[k]);
                if k > 0 && w <= 0.0 {
                    continue;
                }
                let to = spans[g];
                let dst = (to.first + same_place(j, from.count, to.count)) as usize;
                // The nearest (k = 0) takes what is left.
                let part = if k == 0 {
                    water[src]
                } else {
                    (q as f64 * w as f64).floor() as u32
                };
                move_quanta(water, src, dst, part);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(first: u32, count: u32, host: u32) -> GuideSpan {
        GuideSpan {
            first,
            rest: 0,
            count,
            host,
        }
    }

    /// Two guides, host strands 0 and 1, and four followers: guide 0 stands for itself, two
    /// whole followers and half of a third; guide 1 for the rest. The bundles add to the
    /// groom's strands.
    #[test]
    fn bundles_hold_the_groom_s_hair() {
        let own = |g| Follow::own(g);
        let half = Follow {
            guides: [0, 1, 0],
            weights: [0.5, 0.5, 0.0],
        };
        let follow = [own(0), own(1), own(0), own(0), half, own(1)];
        let b = bundles(&follow, &[1.0; 6], &[0, 1, 7]);
        assert_eq!(b, vec![3.5, 2.5, 1.0], "guide 2 is not simulated: itself");
        assert_eq!(b[0] + b[1], 6.0);
        // A follower twice as heavy as its guide counts twice.
        let b = bundles(&[own(0), own(0)], &[1.0, 2.0], &[0]);
        assert_eq!(b, vec![3.0]);
    }

    /// Water moved by a higher and then a lower fraction is neither made nor lost, and what a
    /// dropped guide held ends with the guides its strand follows.
    #[test]
    fn moves_keep_every_quantum() {
        // Guides 0 and 1 (4 points each), guide 2 (3 points) added, then dropped.
        let spans = [span(0, 4, 0), span(4, 4, 1), span(8, 3, 2)];
        let host_of = [0, 1, 2];
        let mass = [1.0f32; 3];
        let before = [
            Follow::own(0),
            Follow::own(1),
            Follow {
                guides: [0, 1, 0],
                weights: [0.75, 0.25, 0.0],
            },
        ];
        let b = bundles(&before, &mass, &host_of[..2]);
        assert_eq!(b, vec![1.75, 1.25]);
        let mut water = vec![710, 711, 712, 713, 510, 511, 512, 513, 0, 0, 0];
        let total: u64 = water.iter().map(|&q| q as u64).sum();
        take_shares(&mut water, 2..3, &before, &b, &spans, &host_of, &mass);
        assert_eq!(water.iter().map(|&q| q as u64).sum::<u64>(), total);
        // Guide 2 took 0.75 / 1.75 of guide 0's and 0.25 / 1.25 of guide 1's.
        let share = |q: u32, s: f64| (q as f64 * s).floor() as u32;
        let (s0, s1) = (0.75 / 1.75, 0.25 / 1.25);
        assert_eq!((share(710, s0), share(510, s1)), (304, 102));
        assert_eq!(water[8], 304 + 102);
        assert_eq!(water[0], 710 - 304);
        // Its last point reads the guides' last (same fraction of length).
        assert_eq!(water[10], share(713, s0) + share(513, s1));
        let after = water.clone();
        give_back(&mut water, 2..3, &before, &spans, &host_of);
        assert_eq!(water.iter().map(|&q| q as u64).sum::<u64>(), total);
        assert_eq!(&water[8..], &[0, 0, 0], "a dropped guide holds nothing");
        assert_eq!(water[4], after[4] + (after[8] as f64 * 0.25).floor() as u32);
        assert_eq!(water[0], after[0] + after[8] - (after[8] as f64 * 0.25).floor() as u32);
    }
}
