//! The uniform grid that finds the water particles near a hair point (METHOD.md §4), rebuilt
//! by a counting sort every substep.
//!
//! Cells are cubes of side `cell >= r_max`, indexed by `floor(p / cell)` over all of space and
//! hashed into a table twice the particle count (a power of two). Hashing instead of the paper's
//! clamped box means there is no box to outgrow: a point anywhere is found, with no lost
//! neighbour and no out-of-bounds index, and the table's size follows the particle count, not
//! the domain. Two cells that share a bucket only add candidates, which the caller's distance
//! test rejects; a query never visits one bucket twice.

use glam::{IVec3, Vec3};

/// A hashed uniform grid over a set of points (the water particles).
#[derive(Debug, Clone)]
pub struct HashGrid {
    cell: f32,
    inv_cell: f32,
    mask: u32,
    /// Bucket `b` holds `sorted[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    cursor: Vec<u32>,
    sorted: Vec<u32>,
    bucket_of: Vec<u32>,
    lo: Vec3,
    hi: Vec3,
}

/// Cell coordinates saturate at ±2^20 so that far-away points hash without overflow.
const COORD_LIMIT: f32 = (1 << 20) as f32;

impl HashGrid {
    /// A grid for up to `capacity` points with cubic cells of side `cell` (m); allocates
    /// everything it will ever need so that [`HashGrid::build`] does not allocate.
    pub fn new(capacity: usize, cell: f32) -> Self {
        let table = Self::table_size(capacity);
        HashGrid {
            cell,
            inv_cell: 1.0 / cell,
            mask: 0,
            start: Vec::with_capacity(table + 1),
            cursor: Vec::with_capacity(table),
            sorted: Vec::with_capacity(capacity),
            bucket_of: Vec::with_capacity(capacity),
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
        }
    }

    fn table_size(n: usize) -> usize {
        (2 * n).next_power_of_two().max(16)
    }

    /// Cell side, m.
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Integer cell of a position (eq. 4 without the clamp).
    #[inline(always)]
    pub fn cell_of(&self, p: Vec3) -> IVec3 {
        let c = (p * self.inv_cell).floor().clamp(Vec3::splat(-COORD_LIMIT), Vec3::splat(COORD_LIMIT));
        // NaN maps to cell 0 (`as` saturates); callers reject non-finite state elsewhere.
        IVec3::new(c.x as i32, c.y as i32, c.z as i32)
    }

    /// Bucket of a cell (eq. 5's linear index, hashed).
    #[inline(always)]
    fn bucket(&self, c: IVec3) -> u32 {
        let h = (c.x as u32).wrapping_mul(73_856_093)
            ^ (c.y as u32).wrapping_mul(19_349_663)
            ^ (c.z as u32).wrapping_mul(83_492_791);
        h & self.mask
    }

    /// Rebuilds the grid over `points` by counting sort: count per bucket, prefix sum, scatter.
    pub fn build(&mut self, points: &[Vec3]) {
        let n = points.len();
        let table = Self::table_size(n);
        self.mask = table as u32 - 1;
        self.start.clear();
        self.start.resize(table + 1, 0);
        self.bucket_of.clear();
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &p in points {
            let b = self.bucket(self.cell_of(p));
            self.bucket_of.push(b);
            self.start[b as usize + 1] += 1;
            lo = lo.min(p);
            hi = hi.max(p);
        }
        for b in 0..table {
            self.start[b + 1] += self.start[b];
        }
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.start[..table]);
        self.sorted.clear();
        self.sorted.resize(n, 0);
        for (i, &b) in self.bucket_of.iter().enumerate() {
            let slot = &mut self.cursor[b as usize];
            self.sorted[*slot as usize] = i as u32;
            *slot += 1;
        }
        (self.lo, self.hi) = (lo, hi);
    }

    /// Number of points in the grid.
    pub fn len(&self) -> usize {
        self.sorted.len()
    }

    /// Whether the grid holds no point.
    pub fn is_empty(&self) -> bool {
        self.sorted.is_empty()
    }

    /// Whether a point within `r` of `p` can exist: `p` lies in the points' bounds grown by `r`.
    #[inline(always)]
    pub fn may_have_near(&self, p: Vec3, r: f32) -> bool {
        p.cmpge(self.lo - r).all() && p.cmple(self.hi + r).all()
    }

    /// Calls `f(index)` for every point in the cells that overlap the cube `p ± r`: a superset of
    /// the points within `r` when `r <= cell`. Each point is visited at most once.
    #[inline]
    pub fn for_each_candidate(&self, p: Vec3, r: f32, mut f: impl FnMut(u32)) {
        let a = self.cell_of(p - r);
        let b = self.cell_of(p + r);
        let mut seen = [u32::MAX; 27];
        let mut n_seen = 0;
        for cx in a.x..=b.x.min(a.x + 2) {
            for cy in a.y..=b.y.min(a.y + 2) {
                for cz in a.z..=b.z.min(a.z + 2) {
                    let bucket = self.bucket(IVec3::new(cx, cy, cz));
                    let (s, e) = (self.start[bucket as usize], self.start[bucket as usize + 1]);
                    if s == e || seen[..n_seen].contains(&bucket) {
                        continue;
                    }
                    seen[n_seen] = bucket;
                    n_seen += 1;
                    for &i in &self.sorted[s as usize..e as usize] {
                        f(i);
                    }
                }
            }
        }
    }

    /// Number of points per bucket (for tests and parity checks).
    pub fn bucket_counts(&self) -> Vec<u32> {
        self.start.windows(2).map(|w| w[1] - w[0]).collect()
    }
}
