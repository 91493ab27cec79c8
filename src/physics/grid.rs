//! The uniform grid that finds the water particles near a hair point (METHOD.md §4), rebuilt
//! by a counting sort (count, prefix sum, scatter) every substep.
//!
//! The grid box is the points' own bounds, rebuilt with them, cut into cubic cells of side
//! `>= cell_min`; cells grow when the box would need more than [`MAX_CELLS`] (or 64 per point,
//! so that a few particles spread wide do not clear a large table every substep). Indices follow
//! eq. 4 (clamped) and eq. 5 (`A = C_z + N_z (C_y + N_y C_x)`). A query from anywhere is
//! exact: a point farther than `r` from the box has no neighbour and returns at once, and
//! clamping is monotonic, so a neighbour's cell always lies in the clamped query range. Cells
//! adjacent in z are adjacent in memory, so a query walks one contiguous run per (x, y).
//!
//! Beside the cells, a bit per cell of a finer grid over the same box (cells of `cell_min`,
//! growing only when the box needs more than the bits allocated) marks where a point may be
//! within `cell_min`: the prefilter [`Grid::may_have_near_lanes`] reads it. The cells of the
//! counting sort grow with a wide box (under rain over a head, 2.5 cm cells for an 8 mm
//! reach), and their 3 x 3 x 3 neighbourhoods let three quarters of a groom's points through
//! where one in twenty is near a particle; the fine bits let through one in five.

use super::counting_sort::CountingSort;

#[cfg(target_arch = "x86_64")]
mod avx2;
use glam::{IVec3, Vec3};

/// Most cells a grid uses; a larger box gets larger cells instead.
pub const MAX_CELLS: usize = 1 << 18;

/// Bits of the prefilter's fine grid: 1 MiB, what the sort cells' flags took before, enough
/// for a box of a metre at 8 mm (the bench's rain over a head needs 4 million). A box that
/// needs more gets larger fine cells.
const FINE_BITS: usize = 1 << 23;

/// A uniform grid over a set of points (the water particles, or strand tips).
#[derive(Debug, Clone)]
pub struct Grid {
    cell_min: f32,
    cell: f32,
    inv_cell: f32,
    lo: Vec3,
    hi: Vec3,
    dims: IVec3,
    /// The points by cell: cell `c` holds `order.sorted[order.start[c]..order.start[c + 1]]`.
    order: CountingSort,
    cell_of_point: Vec<u32>,
    /// The prefilter's fine grid: the inverse of its cell side, cells per axis, and a bit per
    /// cell set where some point lies within `cell_min` of the cell.
    fine_inv: f32,
    fine_dims: IVec3,
    near: Vec<u64>,
    /// Whether builds mark the prefilter's bits (a grid made by
    /// [`Grid::without_prefilter`] does not, and its prefilter passes every point in its box).
    filtered: bool,
}

impl Grid {
    /// A grid for up to `capacity` points with cells of side at least `cell_min` (m); it
    /// allocates all it will need, so [`Grid::build`] does not allocate.
    pub fn new(capacity: usize, cell_min: f32) -> Self {
        Grid::made(capacity, cell_min, true)
    }

    /// [`Grid::new`] for callers that only query cells (`runs_in_box`, `for_each_candidate`):
    /// builds skip the prefilter's bits, a pass over every point and its 27 fine cells that
    /// took as long as the rest of a build.
    pub fn without_prefilter(capacity: usize, cell_min: f32) -> Self {
        Grid::made(capacity, cell_min, false)
    }

    /// The grid of [`Grid::new`] (`filtered`) or of [`Grid::without_prefilter`].
    fn made(capacity: usize, cell_min: f32, filtered: bool) -> Self {
        Grid {
            cell_min,
            cell: cell_min,
            inv_cell: 1.0 / cell_min,
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            dims: IVec3::ONE,
            order: CountingSort::with_capacity(MAX_CELLS, capacity),
            cell_of_point: Vec::with_capacity(capacity),
            fine_inv: 1.0 / cell_min,
            fine_dims: IVec3::ONE,
            near: Vec::with_capacity(if filtered { FINE_BITS / 64 } else { 0 }),
            filtered,
        }
    }

    /// Cell side now in use, m.
    pub fn cell(&self) -> f32 {
        self.cell
    }

    /// Cells per axis now in use.
    pub fn dims(&self) -> IVec3 {
        self.dims
    }

    /// Clamped cell coordinates of a position (eq. 4). NaN maps to cell 0.
    #[inline(always)]
    pub fn cell_of(&self, p: Vec3) -> IVec3 {
        let c = ((p - self.lo) * self.inv_cell).clamp(Vec3::ZERO, (self.dims - IVec3::ONE).as_vec3());
        // Truncation is floor for non-negative values, and avoids a libm call on baseline x86-64.
        IVec3::new(c.x as i32, c.y as i32, c.z as i32)
    }

    /// Linear index of a cell (eq. 5).
    #[inline(always)]
    fn index(&self, c: IVec3) -> usize {
        ((c.x * self.dims.y + c.y) * self.dims.z + c.z) as usize
    }

    /// Clamped fine cell of a position (eq. 4 on the fine grid; monotonic in each coordinate,
    /// so a point within `cell_min` of another lies in the range the other marks).
    #[inline(always)]
    fn fine_of(&self, p: Vec3) -> IVec3 {
        let c = ((p - self.lo) * self.fine_inv).clamp(Vec3::ZERO, (self.fine_dims - IVec3::ONE).as_vec3());
        IVec3::new(c.x as i32, c.y as i32, c.z as i32)
    }

    /// Rebuilds the grid over `points`: box, cell size, count, prefix sum, scatter.
    pub fn build(&mut self, points: &[Vec3]) {
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &p in points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if points.is_empty() {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        // Cells per side in f32 as the GPU computes them, counted in f64 so the product cannot
        // overflow; a box too wide for f32 (points up to FLT_MAX apart) is measured in f64.
        // The cell grows until the count fits, so any finite box works.
        let extent = hi - lo;
        let extent_f64 = hi.as_dvec3() - lo.as_dvec3();
        let mut cell = self.cell_min;
        let dims_for = |cell: f32| {
            let d = if extent.is_finite() {
                (extent / cell).as_dvec3()
            } else {
                extent_f64 / cell as f64
            };
            d.floor().max(glam::DVec3::ZERO) + 1.0
        };
        let mut dims = dims_for(cell);
        // Few points spread wide need few cells: every build clears and prefix-sums all of them.
        let max_cells = (64 * points.len()).clamp(4096, MAX_CELLS) as f64;
        while dims.element_product() > max_cells {
            cell *= 1.26; // about 2x fewer cells per round
            dims = dims_for(cell);
        }
        let dims = dims.as_ivec3();
        (self.lo, self.hi, self.cell, self.inv_cell, self.dims) = (lo, hi, cell, 1.0 / cell, dims);
        // The fine grid: cells of `cell_min`, grown as the cells are when the box needs more
        // bits than were allocated.
        let mut fine = self.cell_min;
        let mut fine_dims = dims_for(fine);
        while fine_dims.element_product() > FINE_BITS as f64 {
            fine *= 1.26;
            fine_dims = dims_for(fine);
        }
        (self.fine_inv, self.fine_dims) = (1.0 / fine, fine_dims.as_ivec3());
        let cells = dims.element_product() as usize;
        self.cell_of_point.clear();
        for &p in points {
            let c = self.index(self.cell_of(p)) as u32;
            self.cell_of_point.push(c);
        }
        self.order.sort(&self.cell_of_point, cells);
        if self.filtered {
            self.mark_fine(points);
        }
    }

    /// Sets the fine bits of the cells each point's cube of half-side `cell_min` touches (at
    /// most 3 x 3 x 3: fine cells are at least `cell_min`); each (x, y) is one run of bits.
    ///
    /// The points are taken in cell order, and a run of them that fits in a box of side
    /// `cell_min` is marked as one: the box's cube holds each point's cube, and `fine_of` is
    /// monotonic, so no cell a point's cube touches is left out; at most one fine cell more a
    /// side is marked. Dense water marks far fewer boxes than points (a million drops in the
    /// paper scene's hair: most of the build's time went to marking the same cells again).
    fn mark_fine(&mut self, points: &[Vec3]) {
        let words = (self.fine_dims.element_product() as usize).div_ceil(64);
        self.near.clear();
        self.near.resize(words, 0);
        let r = Vec3::splat(self.cell_min);
        let mut run: Option<(Vec3, Vec3)> = None;
        for &j in &self.order.sorted {
            let p = points[j as usize];
            if let Some((lo, hi)) = &mut run {
                let (l, h) = (lo.min(p), hi.max(p));
                if (h - l).cmple(r).all() {
                    (*lo, *hi) = (l, h);
                    continue;
                }
                let (a, b) = (self.fine_of(*lo - r), self.fine_of(*hi + r));
                mark_box(&mut self.near, self.fine_dims, a, b);
            }
            run = Some((p, p));
        }
        if let Some((lo, hi)) = run {
            let (a, b) = (self.fine_of(lo - r), self.fine_of(hi + r));
            mark_box(&mut self.near, self.fine_dims, a, b);
        }
    }

    /// The fine bit of the cell holding `p`.
    #[inline(always)]
    fn fine_bit(&self, p: Vec3) -> bool {
        let c = self.fine_of(p);
        let bit = ((c.x * self.fine_dims.y + c.y) * self.fine_dims.z + c.z) as usize;
        self.near[bit / 64] & (1 << (bit % 64)) != 0
    }

    /// False when no point can lie within `r` of `p` (`r` at most `cell_min`): `p` is outside
    /// the box grown by `r`, or its fine cell is unmarked. A point within `r` of `p` marked
    /// every fine cell its cube of half-side `cell_min` touches, `p`'s among them (clamping
    /// keeps the order of coordinates, so it keeps `p` inside that range).
    #[inline(always)]
    pub fn may_have_near(&self, p: Vec3, r: f32) -> bool {
        debug_assert!(r <= self.cell_min);
        let in_box = p.cmpge(self.lo - r).all() && p.cmple(self.hi + r).all();
        if !self.filtered {
            return in_box;
        }
        in_box && !self.near.is_empty() && self.fine_bit(p)
    }

    /// [`Grid::may_have_near`] for the `W` points of a lane row at once (the arithmetic runs
    /// as SIMD; only the flag lookups are scalar). Returns a bit per lane.
    #[inline(always)]
    pub fn may_have_near_lanes(&self, x: &crate::physics::lanes::L3, r: f32) -> u32 {
        use crate::physics::lanes::W;
        debug_assert!(r <= self.cell_min);
        if self.filtered && self.near.is_empty() {
            return 0;
        }
        let (lo, hi, inv) = (self.lo - r, self.hi + r, self.fine_inv);
        if !self.filtered {
            let mut bits = 0u32;
            for l in 0..W {
                let (px, py, pz) = (x.x[l], x.y[l], x.z[l]);
                let inside = (px >= lo.x) & (px <= hi.x) & (py >= lo.y) & (py <= hi.y) & (pz >= lo.z) & (pz <= hi.z);
                bits |= (inside as u32) << l;
            }
            return bits;
        }
        let top = (self.fine_dims - IVec3::ONE).as_vec3();
        let mut idx = [0i32; W];
        let mut inside = [false; W];
        for l in 0..W {
            let (px, py, pz) = (x.x[l], x.y[l], x.z[l]);
            inside[l] = (px >= lo.x) & (px <= hi.x) & (py >= lo.y) & (py <= hi.y) & (pz >= lo.z) & (pz <= hi.z);
            let cx = ((px - self.lo.x) * inv).clamp(0.0, top.x) as i32;
            let cy = ((py - self.lo.y) * inv).clamp(0.0, top.y) as i32;
            let cz = ((pz - self.lo.z) * inv).clamp(0.0, top.z) as i32;
            idx[l] = (cx * self.fine_dims.y + cy) * self.fine_dims.z + cz;
        }
        let mut bits = 0u32;
        for l in 0..W {
            let i = idx[l] as usize;
            // SAFETY: each coordinate is clamped to [0, fine_dims - 1], so i is below the
            // fine cell count, and `near` holds that many bits after a build.
            let flag = (unsafe { *self.near.get_unchecked(i / 64) } >> (i % 64)) as u32 & 1;
            bits |= ((inside[l] as u32) & flag) << l;
        }
        bits
    }

    /// Bytes allocated.
    pub fn bytes(&self) -> usize {
        self.order.bytes() + 4 * self.cell_of_point.capacity() + 8 * self.near.capacity()
    }

    /// Number of points in the grid.
    pub fn len(&self) -> usize {
        self.order.sorted.len()
    }

    /// Whether the grid holds no point.
    pub fn is_empty(&self) -> bool {
        self.order.sorted.is_empty()
    }

    /// Writes into `out` the runs `(start, end)` of sorted slots whose cells overlap the box
    /// `qlo..qhi` (one per (x, y) column, empty ones left out) and returns how many; `None` when
    /// the box spans more than `out.len()` columns. No closure: the caller's loop stays in the
    /// caller's instruction set (a closure would be compiled without AVX2 and called per run).
    #[inline(always)]
    pub fn runs_in_box(&self, qlo: Vec3, qhi: Vec3, out: &mut [(u32, u32)]) -> Option<usize> {
        if !(qlo.cmple(self.hi).all() && qhi.cmpge(self.lo).all()) || self.order.sorted.is_empty() {
            return Some(0);
        }
        let a = self.cell_of(qlo);
        let b = self.cell_of(qhi);
        if ((b.x - a.x + 1) * (b.y - a.y + 1)) as usize > out.len() {
            return None;
        }
        let span = (b.z - a.z) as usize;
        let mut n = 0;
        for cx in a.x..=b.x {
            let mut first = self.index(IVec3::new(cx, a.y, a.z));
            for _ in a.y..=b.y {
                let (s, e) = (self.order.start[first], self.order.start[first + span + 1]);
                out[n] = (s, e);
                n += (s < e) as usize;
                first += self.dims.z as usize;
            }
        }
        Some(n)
    }

    /// Calls `f(index)` for every point in the cells that overlap the cube `p ± r`: a superset of
    /// the points within `r` of `p` (`r` at most the cell size), each visited once.
    #[inline(always)]
    pub fn for_each_candidate(&self, p: Vec3, r: f32, mut f: impl FnMut(u32)) {
        // A cube of side 2r <= 2 cells spans 3 columns per axis, or 4 when rounding puts a
        // face just past a cell boundary: 4 x 4 always suffices.
        let mut runs = [(0u32, 0u32); 16];
        let n = self
            .runs_in_box(p - r, p + r, &mut runs)
            .expect("r <= cell: a cube spans at most 4 x 4 columns");
        for &(s, e) in &runs[..n] {
            self.order.sorted[s as usize..e as usize].iter().for_each(|&i| f(i));
        }
    }

    /// Point index at each sorted slot (points grouped by cell).
    pub fn sorted(&self) -> &[u32] {
        &self.order.sorted
    }

    /// Number of points per cell (tests and GPU parity).
    pub fn cell_counts(&self) -> Vec<u32> {
        self.order.start.windows(2).map(|w| w[1] - w[0]).collect()
    }
}

/// Sets the bits of fine cells `a..=b` (a box of them, `fd` a side): one run of bits per
/// (x, y).
#[inline(always)]
fn mark_box(words: &mut [u64], fd: IVec3, a: IVec3, b: IVec3) {
    for x in a.x..=b.x {
        for y in a.y..=b.y {
            let row = ((x * fd.y + y) * fd.z) as usize;
            set_bits(words, row + a.z as usize, row + b.z as usize);
        }
    }
}

/// Sets bits `a..=b` of `words` (bit `i` is bit `i % 64` of word `i / 64`) a word at a time.
/// Bit by bit, each set read back the word the last one wrote, and marking the prefilter's
/// bits took most of a grid build.
#[inline(always)]
fn set_bits(words: &mut [u64], a: usize, b: usize) {
    let (wa, wb) = (a / 64, b / 64);
    let from = u64::MAX << (a % 64);
    let to = u64::MAX >> (63 - b % 64);
    if wa == wb {
        words[wa] |= from & to;
        return;
    }
    words[wa] |= from;
    words[wa + 1..wb].fill(u64::MAX);
    words[wb] |= to;
}

#[cfg(test)]
mod tests {
    use super::Grid;
    use crate::physics::lanes::{L3, W};
    use glam::Vec3;

    /// A grid without the prefilter finds the same runs as one with it, and its prefilter
    /// passes every point the filtered one passes (it may pass more, never fewer).
    #[test]
    fn a_grid_without_prefilter_queries_the_same_cells() {
        let mut rng = crate::scenes::Lcg(5);
        let mut r = || rng.next_f32();
        let pts: Vec<Vec3> = (0..500).map(|_| Vec3::new(r(), r(), r()) * 0.2).collect();
        let (mut a, mut b) = (Grid::new(pts.len(), 0.01), Grid::without_prefilter(pts.len(), 0.01));
        a.build(&pts);
        b.build(&pts);
        assert_eq!((a.dims(), a.cell(), a.sorted()), (b.dims(), b.cell(), b.sorted()));
        let (mut ra, mut rb) = ([(0u32, 0u32); 64], [(0u32, 0u32); 64]);
        for _ in 0..300 {
            let p = Vec3::new(r(), r(), r()) * 0.3 - Vec3::splat(0.05);
            let (na, nb) = (
                a.runs_in_box(p - 0.01, p + 0.01, &mut ra),
                b.runs_in_box(p - 0.01, p + 0.01, &mut rb),
            );
            assert_eq!(na, nb);
            let n = na.expect("a 2 cm box spans few columns");
            assert_eq!(ra[..n], rb[..n]);
            assert!(b.may_have_near(p, 0.01) || !a.may_have_near(p, 0.01));
            let mut row = L3::ZERO;
            for l in 0..W {
                row.set(l, p + Vec3::new(0.004 * l as f32, 0.0, 0.0));
            }
            let (fa, fb) = (a.may_have_near_lanes(&row, 0.01), b.may_have_near_lanes(&row, 0.01));
            assert_eq!(fa & fb, fa, "lanes {fa:08b} against {fb:08b}");
        }
    }

    /// A run set a word at a time sets exactly the bits of the run, within a word, across
    /// one boundary and across several.
    #[test]
    fn set_bits_sets_the_run_and_nothing_else() {
        for (a, b) in [
            (0, 0),
            (3, 5),
            (60, 63),
            (63, 64),
            (62, 130),
            (64, 127),
            (5, 250),
            (191, 191),
        ] {
            let mut words = [0u64; 4];
            super::set_bits(&mut words, a, b);
            for i in 0..256 {
                let set = words[i / 64] >> (i % 64) & 1 == 1;
                assert_eq!(set, (a..=b).contains(&i), "run {a}..={b}, bit {i}");
            }
        }
    }
}
