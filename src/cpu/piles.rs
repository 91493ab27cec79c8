//! Drops that meet coalesce and pull as one (docs/METHOD.md §2, "Drops that meet").
//!
//! The paper's model has no force between particles, so drops that fall into one well of the
//! hair settle on one equilibrium: on the paper scene with 1,000 drops, the 713 held drops
//! sit at 240 places a tenth of a millimetre across after 300 frames, a quarter of them
//! exactly where another is, and three pairs of eq. 2 in four are a hair point pulled again
//! by a drop next to one that already pulls it. With [`crate::WaterParams::pile_cell`] > 0,
//! drops whose positions fall in one cell of that side at a step's start coalesce: each takes
//! their mean position and mean velocity (the centre of mass and the momentum are kept; the
//! motion between them is lost, as when real drops merge), and from then on they are one
//! source of eq. 2, pulling with their summed strength from their common place, each taking
//! an equal share of the source's reaction. So they stay together, bit for bit, and the host
//! still sees every drop (they are drawn at one place).
//!
//! Grouping without the coalescence (each drop kept where it was, the source at their mean)
//! was tried first and not kept: a pile's drops then took equal shares and kept their
//! offsets, so drops no longer settled onto one place: 539 sources were left of 713 drops
//! after 250 frames, where the exact model's drops sit at 240 places after 300
//! (docs/PERFORMANCE.md, 2026-12-02).
//!
//! The grouping is made once a step, before the first substep's grid build, by each drop's
//! cell, then its index (the same on every run and thread count), and the means are sums of
//! fixed-point offsets (exact, so the same whatever order the drops come in); each substep then
//! builds the water grid over the sources instead of the drops. A step with no cell holding
//! two drops runs as though coalescence were off, with the same bits. Only the paper's model
//! coalesces: with held water each particle carries its own water and the hair asks each one
//! for it (`physics/absorb.rs`).

use crate::physics::grid::Grid;
use glam::{Vec3, Vec4};

/// The fixed-point unit of a coalescing drop's offset in its cell, in cells: 2⁻²⁰ (0.1 nm
/// in a 0.1 mm cell).
pub(crate) const POSITION_UNIT: f32 = 1.0 / (1u32 << 20) as f32;

/// The fixed-point unit of a coalescing drop's velocity, m/s: 2⁻²⁴ (a sum of 64-bit integers
/// holds ±5·10¹¹ m/s).
pub(crate) const VELOCITY_UNIT: f32 = 1.0 / (1u32 << 24) as f32;

/// The mean of `v` about `origin`, each offset rounded to a whole number of `unit` and the
/// offsets summed as integers: exact, so the same whatever order the drops come in.
fn fixed_mean(v: &[Vec3], origin: Vec3, unit: f32) -> Vec3 {
    let inv = 1.0 / unit;
    let sum = v.iter().fold([0i64; 3], |s, &p| {
        let q = (p - origin) * inv;
        [0, 1, 2].map(|c| s[c] + q[c].round() as i64)
    });
    let n = v.len() as f64;
    origin + Vec3::from_array(sum.map(|s| (s as f64 / n) as f32)) * unit
}

/// One step's drops grouped into sources, and the sources in the grid's order.
#[derive(Debug)]
pub struct Piles {
    /// The cell's side, m.
    cell: f32,
    /// Whether some source holds two drops or more this step (else the grouping is unused).
    active: bool,
    /// Each source's first drop in the drops' order, then the number of drops; in the grid's
    /// order once a substep's build has run.
    start: Vec<u32>,
    /// Each source's place (its drops share it), in source order.
    place: Vec<Vec3>,
    /// The drops of each source in the grid's order: eq. 2's strength factor (`Strength`).
    drops: Vec<f32>,
    /// Each drop's source in the grid's order.
    slot_of: Vec<u32>,
    /// Scratch: each drop's cell and index, sorted.
    keyed: Vec<([i32; 3], u32)>,
    /// Scratch: the drops' moves and the new starts.
    moved: (Vec<Vec3>, Vec<Vec3>, Vec<u32>),
    /// Each drop's share of its source's force (`share`).
    per_drop: Vec<Vec4>,
}

impl Piles {
    /// Groups by cells of side `cell` (m, > 0), with room for `capacity` drops.
    pub fn new(cell: f32, capacity: usize) -> Piles {
        Piles {
            cell,
            active: false,
            start: Vec::with_capacity(capacity + 1),
            place: Vec::with_capacity(capacity),
            drops: Vec::with_capacity(capacity),
            slot_of: Vec::with_capacity(capacity),
            keyed: Vec::with_capacity(capacity),
            moved: (
                Vec::with_capacity(capacity),
                Vec::with_capacity(capacity),
                Vec::with_capacity(capacity + 1),
            ),
            per_drop: Vec::with_capacity(capacity),
        }
    }

    /// Whether this step has a pile (the grid holds sources, not drops).
    pub fn active(&self) -> bool {
        self.active
    }

    /// Forgets the grouping: drops were added or removed since it was made.
    pub fn forget(&mut self) {
        self.active = false;
    }

    /// Drops per grid slot, for eq. 2's strength: empty while no pile is active.
    pub fn drops(&self) -> &[f32] {
        if self.active {
            &self.drops
        } else {
            &[]
        }
    }

    /// Number of sources (the grid's slots while active).
    pub fn sources(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        fn b<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        b(&self.start)
            + b(&self.place)
            + b(&self.drops)
            + b(&self.slot_of)
            + b(&self.keyed)
            + b(&self.moved.0)
            + b(&self.moved.1)
            + b(&self.moved.2)
            + b(&self.per_drop)
    }

    /// Groups the drops at `pos` by cell. Where some cell holds two or more, moves the drops
    /// (`pos`, `vel`) into the grouping's order, coalesces each cell's drops onto their mean
    /// position and velocity, and makes the grouping active for this step.
    pub fn group(&mut self, pos: &mut Vec<Vec3>, vel: &mut Vec<Vec3>) {
        let (cell, inv) = (self.cell, 1.0 / self.cell);
        // `as i32` saturates: a drop kilometres out shares a cell only with drops as far out.
        let cell_of = |p: Vec3| {
            let c = (p * inv).floor();
            [c.x as i32, c.y as i32, c.z as i32]
        };
        self.keyed.clear();
        self.keyed
            .extend(pos.iter().enumerate().map(|(j, &p)| (cell_of(p), j as u32)));
        self.keyed.sort_unstable();
        self.active = self.keyed.windows(2).any(|w| w[0].0 == w[1].0);
        if !self.active {
            return;
        }
        let (p2, v2, _) = &mut self.moved;
        p2.clear();
        v2.clear();
        p2.extend(self.keyed.iter().map(|&(_, j)| pos[j as usize]));
        v2.extend(self.keyed.iter().map(|&(_, j)| vel[j as usize]));
        std::mem::swap(pos, p2);
        std::mem::swap(vel, v2);
        self.start.clear();
        for (k, w) in self.keyed.iter().enumerate() {
            if k == 0 || w.0 != self.keyed[k - 1].0 {
                self.start.push(k as u32);
            }
        }
        self.start.push(self.keyed.len() as u32);
        for s in 0..self.sources() {
            let (a, e) = (self.start[s] as usize, self.start[s + 1] as usize);
            // Drops that already share one place and velocity (coalesced in an earlier step,
            // or twins) are left as they are: their mean is themselves.
            let together = pos[a + 1..e].iter().all(|&p| p == pos[a]) && vel[a + 1..e].iter().all(|&v| v == vel[a]);
            if e - a > 1 && !together {
                let c = self.keyed[a].0;
                let corner = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * cell;
                let p = fixed_mean(&pos[a..e], corner, cell * POSITION_UNIT);
                let v = fixed_mean(&vel[a..e], Vec3::ZERO, VELOCITY_UNIT);
                pos[a..e].fill(p);
                vel[a..e].fill(v);
            }
        }
    }

    /// Pass `water_grid` with piles: the grid over the sources' places, the drops moved into
    /// the grid's order source by source, and `sorted` the places in that order.
    pub fn build(&mut self, pos: &mut Vec<Vec3>, vel: &mut Vec<Vec3>, grid: &mut Grid, sorted: &mut [Vec<f32>; 3]) {
        self.place.clear();
        self.place
            .extend(self.start[..self.sources()].iter().map(|&a| pos[a as usize]));
        grid.build(&self.place);
        let order = grid.sorted();
        let (p2, v2, s2) = &mut self.moved;
        p2.clear();
        v2.clear();
        s2.clear();
        self.drops.clear();
        self.slot_of.clear();
        for (k, &s) in order.iter().enumerate() {
            let (a, e) = (self.start[s as usize] as usize, self.start[s as usize + 1] as usize);
            s2.push(p2.len() as u32);
            p2.extend_from_slice(&pos[a..e]);
            v2.extend_from_slice(&vel[a..e]);
            self.drops.push((e - a) as f32);
            self.slot_of.extend(std::iter::repeat_n(k as u32, e - a));
        }
        s2.push(p2.len() as u32);
        std::mem::swap(pos, p2);
        std::mem::swap(vel, v2);
        std::mem::swap(&mut self.start, s2);
        for (c, s) in sorted.iter_mut().enumerate() {
            s.clear();
            s.extend(order.iter().map(|&k| self.place[k as usize][c]));
        }
    }

    /// Each drop's share of its source's force, from `per_slot` (by grid slot: the reactions
    /// in `xyz`, the stiffness in `w`): an equal share of the force, since the drops weigh
    /// alike, and the whole stiffness, which is per unit of strength (each drop is held as
    /// stiffly as its source).
    pub fn share(&mut self, per_slot: &[Vec4]) -> &[Vec4] {
        self.per_drop.clear();
        self.per_drop.extend(self.slot_of.iter().map(|&k| {
            let f = per_slot[k as usize];
            (f.truncate() / self.drops[k as usize]).extend(f.w)
        }));
        &self.per_drop
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drops in one cell coalesce onto their mean position and velocity and become one source;
    /// a drop alone stays as it was; the result does not depend on the order the drops came in.
    #[test]
    fn drops_in_one_cell_coalesce_into_one_source() {
        // Both inside the cell [0.0102, 0.0103] x [0.0201, 0.0202] x [-0.0004, -0.0003].
        let a = Vec3::new(0.01024, 0.02016, -0.00036);
        let b = a + Vec3::new(0.00002, -0.00002, 0.00001);
        let lone = Vec3::new(0.05, 0.0, 0.0);
        let vel_of = |p: Vec3| Vec3::new(p.y, -p.x, 1.0) * 10.0;
        let mut outs = Vec::new();
        for order in [[a, b, lone], [lone, b, a], [b, lone, a]] {
            let mut pos = order.to_vec();
            let mut vel: Vec<Vec3> = pos.iter().map(|&p| vel_of(p)).collect();
            let (p0, v0): (Vec3, Vec3) = (pos.iter().sum(), vel.iter().sum());
            let mut piles = Piles::new(1.0e-4, 8);
            piles.group(&mut pos, &mut vel);
            assert!(piles.active());
            // The centre of mass and the momentum are kept (to rounding).
            let (p1, v1): (Vec3, Vec3) = (pos.iter().sum(), vel.iter().sum());
            assert!(
                (p1 - p0).length() < 1e-8 && (v1 - v0).length() < 1e-5,
                "{p1} {p0} {v1} {v0}"
            );
            let mut grid = Grid::new(8, 0.008);
            let mut sorted = [vec![], vec![], vec![]];
            piles.build(&mut pos, &mut vel, &mut grid, &mut sorted);
            assert_eq!(piles.sources(), 2);
            let k = piles
                .drops()
                .iter()
                .position(|&n| n == 2.0)
                .expect("a source of two drops");
            let lone_k = 1 - k;
            assert_eq!(piles.drops()[lone_k], 1.0);
            let place = |k: usize| Vec3::new(sorted[0][k], sorted[1][k], sorted[2][k]);
            assert!((place(k) - (a + b) / 2.0).length() < 2e-9);
            assert_eq!(place(lone_k), lone, "a drop alone stays, bit for bit");
            // Both coalesced drops sit at the source's place with one velocity; the lone one
            // kept its own.
            let at_pile: Vec<usize> = (0..3).filter(|&j| pos[j] == place(k)).collect();
            assert_eq!(at_pile.len(), 2);
            assert_eq!(vel[at_pile[0]], vel[at_pile[1]]);
            let j_lone = (0..3).find(|j| !at_pile.contains(j)).unwrap();
            assert_eq!((pos[j_lone], vel[j_lone]), (lone, vel_of(lone)));
            // Shares: the source's force halved for each of its drops, its stiffness whole.
            let per_slot: Vec<Vec4> = (0..2)
                .map(|s| Vec4::new(2.0, 4.0, 6.0, 3.0) * piles.drops()[s])
                .collect();
            let per_drop = piles.share(&per_slot).to_vec();
            assert_eq!(per_drop[at_pile[0]], Vec4::new(2.0, 4.0, 6.0, 6.0));
            assert_eq!(per_drop[j_lone], Vec4::new(2.0, 4.0, 6.0, 3.0));
            outs.push((pos, vel, sorted));
        }
        assert!(
            outs.windows(2).all(|w| w[0] == w[1]),
            "the result follows the drops, not their order"
        );
    }

    /// No cell with two drops: the grouping stays inactive and moves nothing.
    #[test]
    fn drops_apart_are_left_as_they_are() {
        let mut pos = vec![Vec3::ZERO, Vec3::new(0.001, 0.0, 0.0), Vec3::new(0.0, -0.001, 0.0)];
        let mut vel = vec![Vec3::ONE, Vec3::X, Vec3::Y];
        let before = (pos.clone(), vel.clone());
        let mut piles = Piles::new(1.0e-4, 4);
        piles.group(&mut pos, &mut vel);
        assert!(!piles.active());
        assert!(piles.drops().is_empty());
        assert_eq!((pos, vel), before);
    }
}
