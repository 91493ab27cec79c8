//! A hashed uniform grid: cells of a fixed side anywhere in space, stored in a table of about
//! two buckets per point, so a query walks cells as small as its radius however wide the
//! points spread. The water grid ([`super::grid::Grid`]) bounds its table by the box and lets
//! its cells grow when the box is wide; over hair points (a groom spans half a metre, bridges
//! reach millimetres) that made each query walk ~60 times the points it needs.
//!
//! Built by a counting sort over buckets (count, prefix sum, scatter in point order), so a
//! bucket lists its points in index order and queries are deterministic.

use super::counting_sort::CountingSort;
use super::rounding::floor_i32;
use glam::{IVec3, Vec3};
use rayon::prelude::*;

/// Fewest buckets a table has.
pub const MIN_BUCKETS: usize = 64;

/// Buckets of the table over `points` points: the next power of two of twice their number, at
/// least [`MIN_BUCKETS`] (the GPU's water grid sizes its table the same way, `grid.wgsl`).
pub fn buckets_for(points: usize) -> usize {
    (2 * points).next_power_of_two().max(MIN_BUCKETS)
}

/// A hashed grid over a set of points.
#[derive(Debug, Clone)]
pub struct HashGrid {
    cell: f32,
    inv_cell: f32,
    mask: u32,
    /// The points by bucket: bucket `b` holds `order.sorted[order.start[b]..order.start[b + 1]]`.
    order: CountingSort,
    /// The points' positions and indices in bucket order, so a query reads each bucket
    /// contiguously, 16 bytes a point. A bucket also holds other cells' points that hash
    /// alike; a query tells them apart by the cell of the position, worked out only for the
    /// points within reach (a fifth of those a bridge search scans on a soaked groom).
    /// Keeping each point's cell beside it instead cost 12 more bytes a point read, and the
    /// search waits on those reads.
    sorted: Vec<Entry>,
    bucket: Vec<u32>,
}

/// A point in bucket order: its position and index.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(16))]
struct Entry {
    p: [f32; 3],
    index: u32,
}

impl HashGrid {
    /// A grid with cells of side `cell` (m), for queries of radius at most `cell`.
    pub fn new(cell: f32) -> Self {
        HashGrid {
            cell,
            inv_cell: 1.0 / cell,
            mask: 0,
            order: CountingSort::default(),
            sorted: Vec::new(),
            bucket: Vec::new(),
        }
    }

    /// Integer cell of a position ([`coord_at`] with this grid's cell).
    #[inline(always)]
    fn coord_of(&self, p: Vec3) -> IVec3 {
        coord_at(p, self.inv_cell)
    }

    /// Bucket of a cell ([`bucket_at`] with this grid's table).
    #[inline(always)]
    fn bucket_of(&self, c: IVec3) -> u32 {
        bucket_at(c, self.mask)
    }

    /// Rebuilds the grid over `points` (allocates only when they outgrow the last build).
    /// `parallel`: the per-point work runs as rayon tasks (call it inside the caller's pool);
    /// the grid is the same either way.
    pub fn build(&mut self, points: &[Vec3], parallel: bool) {
        let buckets = buckets_for(points.len());
        self.mask = buckets as u32 - 1;
        let (inv_cell, mask) = (self.inv_cell, self.mask);
        self.bucket.resize(points.len(), 0);
        let place = |(b, &p): (&mut u32, &Vec3)| *b = bucket_at(coord_at(p, inv_cell), mask);
        const MIN: usize = 4096;
        if parallel {
            self.bucket
                .par_iter_mut()
                .zip(points.par_iter())
                .with_min_len(MIN)
                .for_each(place);
        } else {
            self.bucket.iter_mut().zip(points).for_each(place);
        }
        self.order.sort(&self.bucket, buckets);
        let order = &self.order.sorted;
        self.sorted.resize(points.len(), Entry::default());
        let gather = |(e, &i): (&mut Entry, &u32)| {
            *e = Entry {
                p: points[i as usize].to_array(),
                index: i,
            }
        };
        if parallel {
            self.sorted
                .par_iter_mut()
                .zip(order.par_iter())
                .with_min_len(MIN)
                .for_each(gather);
        } else {
            self.sorted.iter_mut().zip(order).for_each(gather);
        }
    }

    /// Number of points per bucket (GPU parity: the GPU's water grid is this grid).
    pub fn bucket_counts(&self) -> Vec<u32> {
        self.order.start.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// Calls `f(j, d2)` with every point `j` within `r <= cell` of `p` (squared distance `d2 <
    /// r^2`), each once, cell by cell, in index order within a cell.
    pub fn for_each_near(&self, p: Vec3, r: f32, mut f: impl FnMut(u32, f32)) {
        self.for_each_near_by(p, r, &mut f, |_| f32::INFINITY, |f, j, d2| f(j, d2));
    }

    /// [`HashGrid::for_each_near`] for a nearest-few search: `f(s, j, d2)` keeps its state in
    /// `s`, and `bound(s)` says how far (squared) a point may be and still matter now. The
    /// query's own cell comes first; a cell whose nearest face lies beyond the bound is left
    /// out (in a dense clump the few nearest are all close, and most cells are skipped).
    /// Every point that could matter is still visited: a search that keeps the nearest by a
    /// strict order finds the same set as with no bound.
    pub fn for_each_near_by<S>(
        &self,
        p: Vec3,
        r: f32,
        s: &mut S,
        bound: impl Fn(&S) -> f32,
        mut f: impl FnMut(&mut S, u32, f32),
    ) {
        debug_assert!(r <= self.cell);
        if self.order.sorted.is_empty() {
            return;
        }
        let mut visit = |s: &mut S, c: IVec3| {
            let b = self.bucket_of(c) as usize;
            let run = self.order.start[b] as usize..self.order.start[b + 1] as usize;
            for e in &self.sorted[run] {
                let q = Vec3::from_array(e.p);
                let d2 = (q - p).length_squared();
                if d2 < r * r && self.coord_of(q) == c {
                    f(s, e.index, d2);
                }
            }
        };
        let own = self.coord_of(p);
        visit(s, own);
        // Distance to a cell's box in cells, from the same product `coord_of` floors, less a
        // part in a thousand so rounding never leaves out a cell that holds a match.
        let q = p * self.inv_cell;
        let (lo, hi) = (self.coord_of(p - r), self.coord_of(p + r));
        for x in lo.x..=hi.x {
            for y in lo.y..=hi.y {
                for z in lo.z..=hi.z {
                    let c = IVec3::new(x, y, z);
                    if c == own {
                        continue;
                    }
                    let cf = c.as_vec3();
                    let gap = (cf - q).max(q - (cf + Vec3::ONE)).max(Vec3::ZERO);
                    if gap.length_squared() * self.cell * self.cell * 0.999 > bound(s) {
                        continue;
                    }
                    visit(s, c);
                }
            }
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.order.bytes() + 4 * self.bucket.capacity() + std::mem::size_of::<Entry>() * self.sorted.capacity()
    }
}

/// Integer cell of a position (floor; NaN gives 0, beyond `i32` saturates).
#[inline(always)]
pub fn coord_at(p: Vec3, inv_cell: f32) -> IVec3 {
    let c = p * inv_cell;
    IVec3::new(floor_i32(c.x), floor_i32(c.y), floor_i32(c.z))
}

/// Bucket of a cell: its [`hash_cell`] in a table of `mask + 1` buckets.
#[inline(always)]
fn bucket_at(c: IVec3, mask: u32) -> u32 {
    hash_cell(c) & mask
}

/// A cell's hash: each coordinate folded in by its own odd multiplier after the bits so far
/// were shifted down onto the low ones, then a last shift for the low bits a table keeps
/// (`common.wgsl` `hash_cell`). It replaced an xor of the three coordinates' products,
/// finalised after, under which cells about the origin, where a head puts its hair, shared
/// whole 32-bit hashes: 39,370 hashes for a cube of 64,000 cells (`tests`), and 7-13 % of
/// the occupied cells of the 100,000 x 32 groom with 100,000 drops on it, so a query there
/// scanned 1.6-1.9 times the particles its cells held (1.25 times with this hash, which gives
/// those cells no shared hash).
#[inline(always)]
pub fn hash_cell(c: IVec3) -> u32 {
    let mut h = (c.x as u32).wrapping_mul(0x9e37_79b1);
    h ^= h >> 16;
    h = (h ^ c.y as u32).wrapping_mul(0x85eb_ca77);
    h ^= h >> 13;
    h = (h ^ c.z as u32).wrapping_mul(0xc2b2_ae3d);
    h ^= h >> 16;
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells hash apart as random keys would, where hair lies: a cube of cells about the
    /// origin (both signs of every coordinate: a head at the world's origin), the same cube
    /// far off, and a shell like a scalp. Under a tenth of a per mille share a whole 32-bit
    /// hash (a random hash: about `n^2 / 2^33`, 5 of 208,000), and a table of about two
    /// buckets a cell ([`buckets_for`]) uses within 1 % of the buckets a random hash fills.
    /// The xor of products this replaced gave the cube about the origin 39,370 hashes for
    /// 64,000 cells and filled 34,010 buckets of the 50,636 expected.
    #[test]
    fn cells_hash_apart_as_random_keys() {
        let cube = |o: IVec3, n: i32| {
            (0..n).flat_map(move |x| (0..n).flat_map(move |y| (0..n).map(move |z| o + IVec3::new(x, y, z))))
        };
        let sets: [(&str, Vec<IVec3>); 3] = [
            ("cube about the origin", cube(IVec3::splat(-20), 40).collect()),
            ("cube far off", cube(IVec3::new(5000, -3000, 700), 40).collect()),
            (
                "shell",
                cube(IVec3::splat(-100), 200)
                    .filter(|c| (90.0..92.0).contains(&c.as_vec3().length()))
                    .collect(),
            ),
        ];
        for (name, cells) in sets {
            let n = cells.len();
            let mut hashes: Vec<u32> = cells.iter().map(|&c| hash_cell(c)).collect();
            let buckets = buckets_for(n) as u32;
            let mut used: Vec<u32> = hashes.iter().map(|h| h & (buckets - 1)).collect();
            hashes.sort_unstable();
            hashes.dedup();
            used.sort_unstable();
            used.dedup();
            assert!(
                n - hashes.len() <= n / 10_000,
                "{name}: {} hashes for {n} cells",
                hashes.len()
            );
            let expected = buckets as f64 * (1.0 - (-(n as f64) / buckets as f64).exp());
            let ratio = used.len() as f64 / expected;
            assert!(
                (0.99..1.01).contains(&ratio),
                "{name}: {} buckets used, {expected:.0} expected",
                used.len()
            );
        }
    }
}
