//! Liquid bridges on the CPU (docs/WET_MODEL.md §5): a grid over the wet hair points finds,
//! once per step, the wet points of other strands within reach of each (pass `hair_grid`);
//! every substep each such pair pulls its two points together (pass `cohesion`), gathered per
//! point into a force per row that the block kernel adds. Exists only when bridges are on.

use super::layout::{Layout, StateRow};
use crate::physics::grid::Grid;
use crate::physics::lanes::{L3, W};
use crate::physics::wet;
use glam::Vec3;

/// How far past the bridge length pairs are looked for, so that points closing in during the
/// step are not missed (the force itself ends at the bridge length).
const SEARCH_MARGIN: f32 = 1.25;

/// Pairs found this step and the force they give.
#[derive(Debug)]
pub struct Bridges {
    grid: Grid,
    /// The wet points: row index times `W` plus lane.
    point: Vec<u32>,
    /// Their positions at the step's start (the grid's input).
    pos: Vec<Vec3>,
    /// Their neighbours (indices into `point`), `first[i]..first[i + 1]`.
    first: Vec<u32>,
    nbr: Vec<u32>,
    /// Each pair's spring coefficient, N/m (the same for both directions).
    coef: Vec<f32>,
    /// Scratch: what stiffness each wet point may still take (kept: no allocation per step).
    room: Vec<f32>,
    /// Force per row, N (zero where no bridge acts).
    pub force: Vec<L3>,
    /// Each point's length of hair, m, per row (half of each adjacent segment).
    length: Vec<[f32; W]>,
    kappa: f32,
    d_b: f32,
}

impl Bridges {
    /// Empty, with each point's length of hair from the rest pose.
    pub fn new(lay: &Layout, kappa: f32, d_b: f32) -> Bridges {
        let n_rows = lay.blocks * lay.rows;
        let mut length = vec![[0.0f32; W]; n_rows];
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let n = lay.strand_points(s);
            for i in 0..n.saturating_sub(1) {
                let (r0, r1) = (b * lay.rows + i, b * lay.rows + i + 1);
                let seg = (lay.rest_local[r1].get(l) - lay.rest_local[r0].get(l)).length();
                length[r0][l] += 0.5 * seg;
                length[r1][l] += 0.5 * seg;
            }
        }
        Bridges {
            grid: Grid::new(lay.mass.len(), d_b * SEARCH_MARGIN),
            point: Vec::new(),
            pos: Vec::new(),
            first: Vec::new(),
            nbr: Vec::new(),
            coef: Vec::new(),
            room: Vec::new(),
            force: vec![L3::ZERO; n_rows],
            length,
            kappa,
            d_b,
        }
    }

    /// Whether any pair was found this step (else the cohesion pass is skipped).
    pub fn active(&self) -> bool {
        !self.nbr.is_empty()
    }

    /// Pass `hair_grid`: finds every pair of wet points of different strands within the search
    /// reach, in point order, and gives each its coefficient: the bridge's stiffness
    /// `4 kappa l min(s_i, s_j) / d_b` (peak pull `kappa l s` at `d_b / 2`), capped so that no
    /// point's bridges together exceed a quarter of what an explicit substep `h` holds stably
    /// (`m / (4 h^2)`, shared among its bridges). `params` gives each point's inverse mass.
    pub fn find_pairs(
        &mut self,
        lay: &Layout,
        state: &[StateRow],
        held: &[[u32; W]],
        capacity: &[[u32; W]],
        inv_mass: impl Fn(usize, usize) -> f32,
        h: f32,
    ) {
        for &p in &self.point {
            self.force[p as usize / W] = L3::ZERO;
        }
        self.point.clear();
        self.pos.clear();
        for (r, (w, row)) in held.iter().zip(state).enumerate() {
            for l in 0..W {
                if w[l] > 0 && lay.real_lanes[r] & (1 << l) != 0 {
                    self.point.push((r * W + l) as u32);
                    self.pos.push(row.x.get(l));
                }
            }
        }
        self.first.clear();
        self.nbr.clear();
        self.coef.clear();
        if self.point.len() < 2 {
            return;
        }
        self.grid.build(&self.pos);
        let reach = self.d_b * SEARCH_MARGIN;
        let strand = |p: u32| (p as usize / W / lay.rows, p as usize % W); // (block, lane)
        self.first.push(0);
        for i in 0..self.point.len() {
            let (si, xi) = (strand(self.point[i]), self.pos[i]);
            let start = self.nbr.len();
            self.grid.for_each_candidate(xi, reach, |j| {
                let j = j as usize;
                if strand(self.point[j]) != si && (self.pos[j] - xi).length_squared() < reach * reach {
                    self.nbr.push(j as u32);
                }
            });
            // The grid visits candidates cell by cell; sorting makes the list (and so the
            // force sum) depend only on which points are near, not on the grid's shape.
            self.nbr[start..].sort_unstable();
            self.first.push(self.nbr.len() as u32);
        }
        let sat = |p: u32| {
            let (r, l) = (p as usize / W, p as usize % W);
            wet::saturation(held[r][l], capacity[r][l]).min(1.0)
        };
        let len = |p: u32| self.length[p as usize / W][p as usize % W];
        // What each point may take: m / (4 h^2 n) (pinned points take anything).
        self.room.clear();
        self.room.extend((0..self.point.len()).map(|i| {
            let p = self.point[i] as usize;
            let w = inv_mass(p / W, p % W);
            let n = (self.first[i + 1] - self.first[i]).max(1) as f32;
            if w > 0.0 {
                1.0 / (w * 4.0 * h * h * n)
            } else {
                f32::INFINITY
            }
        }));
        let room = &self.room;
        for i in 0..self.point.len() {
            let pi = self.point[i];
            for k in self.first[i] as usize..self.first[i + 1] as usize {
                let j = self.nbr[k] as usize;
                let pj = self.point[j];
                let l = 0.5 * (len(pi) + len(pj));
                let stiff = wet::bridge_stiffness(self.kappa, l, sat(pi), sat(pj), self.d_b);
                self.coef.push(stiff.min(room[i].min(room[j])));
            }
        }
    }

    /// Pass `cohesion`: each wet point's pull toward its bridged neighbours at the substep's
    /// start, `c (1 - r / d_b) (x_j - x_i)` for `r < d_b`, summed in neighbour order into the
    /// row force. Each pair's two forces are exact negatives.
    pub fn gather(&mut self, state: &[StateRow]) {
        for i in 0..self.point.len() {
            let p = self.point[i] as usize;
            let (r, l) = (p / W, p % W);
            let xi = state[r].x.get(l);
            let mut f = Vec3::ZERO;
            for k in self.first[i] as usize..self.first[i + 1] as usize {
                let q = self.point[self.nbr[k] as usize] as usize;
                let d = state[q / W].x.get(q % W) - xi;
                f += d * wet::bridge_scale(self.coef[k], d.length(), self.d_b);
            }
            self.force[r].set(l, f);
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.grid.bytes()
            + 4 * (self.point.capacity()
                + self.first.capacity()
                + self.nbr.capacity()
                + self.coef.capacity()
                + self.room.capacity())
            + 12 * self.pos.capacity()
            + std::mem::size_of::<L3>() * self.force.capacity()
            + 4 * W * self.length.capacity()
    }
}
