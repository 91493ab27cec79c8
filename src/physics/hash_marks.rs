//! The GPU water grid's mark table: a bit per hashed cell, set for every cell a point could
//! find a particle from, so a hair point far from all water reads one word and stops instead
//! of hashing its eight cells and reading their buckets (`grid.wgsl` `marked`, read by the
//! adhesion and absorption queries; set by `water.wgsl` `grid_count_cells`). The CPU's water
//! grid has its own prefilter (the dense grid's bits, [`super::grid`]).
//!
//! Why no particle a query would find is left out. The GPU's cells are `2 r_max` a side
//! ([`WATER_CELL_R`]), and a point `x` takes a particle `y` only when `y`
//! is within `r_max` and `y`'s cell lies in the cells `x ± r_max` spans, which are `x`'s own
//! cell and, along each axis, at most the neighbour on the side `x` is nearer. So along an
//! axis `x`'s cell is `y`'s, or `y`'s lower neighbour with `y` within `r_max` (half a cell) of
//! their shared face, or its upper one likewise: a particle marks its own cell and, along each
//! axis, the neighbour on each side whose face it lies within half a cell and
//! [`MARK_MARGIN`] of. The margin is far wider than the rounding of `y / cell` and of the
//! distance test (a relative 1e-7), for positions within a few kilometres of the origin.
//!
//! A particle marks 8 cells, or up to 27 when it lies within the margin of a cell's middle.
//! The table holds [`MARK_WORDS_PER_BUCKET`] words (128 bits) a bucket, at least 256 bits a
//! particle, so about one bit in thirty is set where the particles lie apart. Past
//! [`MAX_MARK_WORDS`] the table stops growing, and past half its words in particles (about
//! half a million) a build has none: every point reads its buckets as before.

use super::hash_grid::{coord_at, hash_cell};
use glam::{IVec3, Vec3};

/// The water grid's cell side on the GPU, in units of `r_max`. At twice the reach a query
/// spans at most 2 cells a side (8 buckets to read, against 27 at one reach) for 2.4 times
/// the volume of candidates. Most hair points lie far from any drop, so the bucket reads
/// dominate: on an H200 the large groom with 1,000 particles took 1.27 ms a step in the hair
/// kernel at two reaches and 3.36 at one (docs/PERFORMANCE.md, "The water's GPU cost, taken
/// apart"). The mark table's argument (above) needs a query's reach to be at most half a cell.
pub const WATER_CELL_R: f32 = 2.0;

/// How far past half a cell a particle still marks the neighbour across the nearer face, in
/// cells.
pub const MARK_MARGIN: f32 = 1.0 / 64.0;

/// Words of the mark table per bucket of the grid.
pub const MARK_WORDS_PER_BUCKET: u32 = 4;

/// The largest mark table, in words (4 MiB).
pub const MAX_MARK_WORDS: u32 = 1 << 20;

/// Words a grid of `max_buckets` buckets keeps room for (its largest table).
pub fn max_mark_words(max_buckets: u32) -> u32 {
    MARK_WORDS_PER_BUCKET.saturating_mul(max_buckets).min(MAX_MARK_WORDS)
}

/// Words of the mark table (a power of two) of a build with `buckets` buckets over
/// `particles` particles, or 0 for none: with more particles than half its words, more than
/// one bit in eight would be set and the table would turn few points away. `water.wgsl`
/// `grid_setup`.
pub fn mark_words(buckets: u32, particles: u32) -> u32 {
    let words = max_mark_words(buckets);
    if particles > words / 2 {
        0
    } else {
        words
    }
}

/// The cells a particle at `y` marks, `lo..=hi` (`water.wgsl` `mark_particle`).
pub fn mark_span(y: Vec3, inv_cell: f32) -> (IVec3, IVec3) {
    let q = y * inv_cell;
    let c = coord_at(y, inv_cell);
    let f = q - q.floor();
    let below = IVec3::new(
        (f.x < 0.5 + MARK_MARGIN) as i32,
        (f.y < 0.5 + MARK_MARGIN) as i32,
        (f.z < 0.5 + MARK_MARGIN) as i32,
    );
    let above = IVec3::new(
        (f.x > 0.5 - MARK_MARGIN) as i32,
        (f.y > 0.5 - MARK_MARGIN) as i32,
        (f.z > 0.5 - MARK_MARGIN) as i32,
    );
    (c.wrapping_sub(below), c.wrapping_add(above))
}

/// Cell `c`'s bit in a table of `words` words (a power of two): its word and bit.
pub fn mark_bit(c: IVec3, words: u32) -> (usize, u32) {
    let i = hash_cell(c) & (32 * words - 1);
    ((i >> 5) as usize, i & 31)
}

/// The table `particles` mark (what the GPU's build writes; tests compare the two).
pub fn marks(particles: &[Vec3], inv_cell: f32, words: u32) -> Vec<u32> {
    let mut table = vec![0u32; words as usize];
    for &y in particles {
        let (lo, hi) = mark_span(y, inv_cell);
        // By offsets from lo (0 to 2 a side, wrapping as the span does), as the GPU loops.
        let n = hi.wrapping_sub(lo);
        for a in 0..=n.x {
            for b in 0..=n.y {
                for k in 0..=n.z {
                    let (w, bit) = mark_bit(lo.wrapping_add(IVec3::new(a, b, k)), words);
                    table[w] |= 1 << bit;
                }
            }
        }
    }
    table
}

/// Whether a point at `x` may have a particle within reach (`grid.wgsl` `marked`).
pub fn marked(table: &[u32], x: Vec3, inv_cell: f32) -> bool {
    let (w, b) = mark_bit(coord_at(x, inv_cell), table.len() as u32);
    table[w] >> b & 1 != 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::Lcg;

    /// Whether the GPU's query from `x` takes the particle at `y` (`adhesion.wgsl`: within
    /// reach, and `y`'s cell among those `x ± r` spans).
    fn query_takes(x: Vec3, y: Vec3, r: f32, inv: f32) -> bool {
        let d = y - x;
        let (c0, c1, cy) = (
            coord_at(x - Vec3::splat(r), inv),
            coord_at(x + Vec3::splat(r), inv),
            coord_at(y, inv),
        );
        d.dot(d) <= r * r && cy.cmpge(c0).all() && cy.cmple(c1).all()
    }

    /// Every particle a query takes lies in a cell its point's cell is marked from, for
    /// pairs at the reach itself, across faces and edges, near the origin and kilometres off.
    #[test]
    fn a_query_never_takes_a_particle_from_an_unmarked_cell() {
        let mut rng = Lcg(77);
        let (mut taken, mut across) = (0, 0);
        for &r in &[0.008f32, 0.0013, 0.05] {
            let cell = WATER_CELL_R * r;
            let inv = 1.0 / cell;
            for &origin in &[0.0f32, 3.7, -120.0, 2000.0] {
                for k in 0..60_000 {
                    let x =
                        Vec3::splat(origin) + Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 * cell;
                    // A direction, then the particle at the reach, just inside it, or anywhere
                    // within it; every fifth along an axis exactly.
                    let mut dir = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5)
                        .normalize_or(Vec3::X);
                    if k % 5 == 0 {
                        dir = [Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::X][k / 5 % 4];
                    }
                    let t = match k % 3 {
                        0 => 1.0,
                        1 => 1.0 - 1e-6,
                        _ => rng.next_f32(),
                    };
                    let y = x + dir * r * t;
                    if !query_takes(x, y, r, inv) {
                        continue;
                    }
                    taken += 1;
                    let (cx, (lo, hi)) = (coord_at(x, inv), mark_span(y, inv));
                    across += (cx != coord_at(y, inv)) as usize;
                    assert!(
                        cx.cmpge(lo).all() && cx.cmple(hi).all(),
                        "r {r}, x {x:?}, y {y:?}: cell {cx} outside the marked {lo}..{hi}"
                    );
                }
            }
        }
        // The cases reach neighbouring cells, not only shared ones.
        assert!(
            taken > 500_000 && across > 200_000,
            "{taken} taken, {across} across a face"
        );
    }

    /// A particle marks 8 cells where it lies away from its cell's middle planes, and the
    /// table a query reads agrees with the spans.
    #[test]
    fn particles_mark_about_eight_cells_and_points_read_them() {
        let (r, mut rng) = (0.008f32, Lcg(3));
        let inv = 1.0 / (WATER_CELL_R * r);
        let ps: Vec<Vec3> = (0..1000)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.5)
            .collect();
        let cells: i32 = ps
            .iter()
            .map(|&y| {
                let (lo, hi) = mark_span(y, inv);
                let n = hi - lo + IVec3::ONE;
                n.x * n.y * n.z
            })
            .sum();
        let mean = cells as f32 / ps.len() as f32;
        assert!((8.0..9.5).contains(&mean), "{mean} cells a particle");
        let words = mark_words(crate::physics::hash_grid::buckets_for(ps.len()) as u32, ps.len() as u32);
        assert_eq!(words, 8192);
        let table = marks(&ps, inv, words);
        let set: u32 = table.iter().map(|w| w.count_ones()).sum();
        // Neighbouring particles share cells, and a few cells share bits.
        assert!(
            set as f32 <= cells as f32 && set as f32 > 0.5 * cells as f32,
            "{set} bits"
        );
        // Every particle's own position reads as marked; most points a metre away do not.
        assert!(ps.iter().all(|&y| marked(&table, y, inv)));
        let far = (0..1000)
            .filter(|_| {
                marked(
                    &table,
                    Vec3::new(rng.next_f32(), rng.next_f32(), 1.0 + rng.next_f32()),
                    inv,
                )
            })
            .count();
        assert!(far < 60, "{far} of 1000 points far from the particles read as marked");
    }

    /// Past half its words in particles a build has no table; the table stops growing at
    /// the cap.
    #[test]
    fn crowds_of_particles_get_no_table() {
        assert_eq!(mark_words(64, 0), 256);
        assert_eq!(mark_words(2048, 1000), 8192);
        assert_eq!(max_mark_words(1 << 21), MAX_MARK_WORDS);
        assert_eq!(mark_words(1 << 21, 1_000_000), 0);
        assert_eq!(mark_words(1 << 19, 200_000), MAX_MARK_WORDS);
    }
}
