//! The strand-major "AoSoA" layout: strands are grouped `W` at a time into blocks; a block is
//! `P` rows (the longest strand's point count), and row `i` holds point `i` of the block's `W`
//! strands as lanes. One spring law then runs on `W` strands per instruction, a block's whole
//! strand state is a few KiB that stays in cache across substeps, and blocks are independent
//! work items for threads.
//!
//! Strands are placed in blocks in Morton (Z-curve) order of their roots, so that a block's
//! strands are neighbours in space: a row's `W` points then share their water-grid cells, and
//! one grid query serves the whole row. A guide groom keeps its own order (its spread order),
//! so that the guides a lower simulated fraction keeps fill the first blocks. The host's strand order is kept everywhere outside
//! (`slot_of_strand`).
//!
//! Shorter strands are padded with pinned points whose springs have k = 0; a last partial block
//! is padded with pinned dummy strands. Padded points are never written to the host.

use crate::groom::Groom;
use crate::params::SimParams;
use crate::physics::lanes::{Lane, L3, W};
pub use crate::physics::lanes::{ParamRow, StateRow};

/// How host strands map to blocks, and the constant per-row data.
#[derive(Debug)]
pub struct Layout {
    /// Rows per block (the longest strand's point count).
    pub rows: usize,
    /// Number of blocks.
    pub blocks: usize,
    /// Number of host strands.
    pub strands: usize,
    /// Host point offsets per strand (len strands + 1).
    pub strand_first: Vec<u32>,
    /// Host strand -> slot (slot = block * W + lane).
    pub slot_of_strand: Vec<u32>,
    /// Slot -> host strand (`strands` or more for a padding lane).
    pub strand_of_slot: Vec<u32>,
    /// Per row: the constant parameters.
    pub params: Vec<ParamRow>,
    /// Per row: rest positions in head space (pinned points' targets; the reset pose).
    pub rest_local: Vec<L3>,
    /// Per row: whether any lane is pinned (only those rows compute head targets).
    pub pinned_row: Vec<bool>,
    /// Per row: bit `l` set when lane `l` is a real hair point (not padding).
    pub real_lanes: Vec<u8>,
    /// Per host point: mass in kg (diagnostics: momentum and energy).
    pub mass: Vec<f32>,
}

impl Layout {
    /// Lays out `groom` with the spring constants of `params`.
    pub fn new(groom: &Groom, params: &SimParams) -> Layout {
        let strands = groom.strand_count();
        let rows = groom.max_strand_points();
        let blocks = strands.div_ceil(W);
        let n_rows = blocks * rows;
        let strand_of_slot = strand_order(groom, params, blocks * W);
        let mut slot_of_strand = vec![0u32; strands];
        for (slot, &s) in strand_of_slot.iter().enumerate() {
            if (s as usize) < strands {
                slot_of_strand[s as usize] = slot as u32;
            }
        }
        let mut lay = Layout {
            rows,
            blocks,
            strands,
            strand_first: groom.strand_first.clone(),
            slot_of_strand,
            strand_of_slot: strand_of_slot.clone(),
            params: vec![ParamRow::default(); n_rows],
            rest_local: vec![L3::ZERO; n_rows],
            pinned_row: vec![false; n_rows],
            real_lanes: vec![0; n_rows],
            mass: groom.mass.clone(),
        };
        let springs = crate::plan::point_springs(groom, params);
        for b in 0..blocks {
            for l in 0..W {
                let slot = b * W + l;
                let s = strand_of_slot[slot] as usize;
                let pts = if s < strands {
                    &groom.positions[groom.strand_range(s)]
                } else {
                    &[][..]
                };
                let first = if s < strands { groom.strand_first[s] as usize } else { 0 };
                for i in 0..rows {
                    let r = b * rows + i;
                    let row = &mut lay.params[r];
                    // Padding sits on the strand's last point (or the origin), pinned.
                    let p = pts.get(i).or(pts.last()).copied().unwrap_or_default();
                    lay.rest_local[r].set(l, p);
                    if i < pts.len() {
                        lay.real_lanes[r] |= 1 << l;
                    }
                    let free = i < pts.len() && !groom.pinned[first + i];
                    row.inv_mass[l] = if free { 1.0 / groom.mass[first + i] } else { 0.0 };
                    if !free {
                        lay.pinned_row[r] = true;
                    }
                    if i + 1 < pts.len() {
                        let sp = &springs[first + i];
                        row.stretch.rest[l] = sp.rest[0];
                        row.stretch.k[l] = sp.stretch.stiffness;
                        row.stretch.c[l] = sp.stretch.damping;
                    }
                    if i + 2 < pts.len() {
                        let sp = &springs[first + i];
                        row.bend.rest[l] = sp.rest[1];
                        row.bend.k[l] = sp.bend.stiffness;
                        row.bend.c[l] = sp.bend.damping;
                    }
                }
            }
        }
        lay
    }

    /// Block and lane of host strand `s`.
    #[inline]
    pub fn lane_of(&self, s: usize) -> (usize, usize) {
        let slot = self.slot_of_strand[s] as usize;
        (slot / W, slot % W)
    }

    /// Points of host strand `s`.
    #[inline]
    pub fn strand_points(&self, s: usize) -> usize {
        (self.strand_first[s + 1] - self.strand_first[s]) as usize
    }

    /// A value per strand (`per_strand`, in the groom's order) as rows of lanes: each of a
    /// strand's points takes its strand's, padding lanes and rows take `pad`.
    pub fn strand_rows(&self, per_strand: &[f32], pad: f32) -> Vec<Lane> {
        let mut out = vec![[pad; W]; self.blocks * self.rows];
        for (s, &v) in per_strand.iter().enumerate().take(self.strands) {
            let (b, l) = self.lane_of(s);
            for i in 0..self.strand_points(s) {
                out[b * self.rows + i][l] = v;
            }
        }
        out
    }

    /// The rest state (positions placed by `head`, zero velocity).
    pub fn rest_state(&self, head: &glam::Affine3A) -> Vec<StateRow> {
        self.rest_local
            .iter()
            .map(|r| StateRow {
                x: r.transformed(head),
                v: L3::ZERO,
            })
            .collect()
    }
}

/// Host strands sorted by the Morton code of their roots ([`crate::physics::morton::order`]),
/// or in the groom's own order when it is a guide groom (its first strands are the ones a
/// lower simulated fraction keeps: they must fill the first blocks), padded with `u32::MAX`
/// to `slots`.
fn strand_order(groom: &Groom, params: &SimParams, slots: usize) -> Vec<u32> {
    let mut order: Vec<u32> = if params.guides.enabled() {
        (0..groom.strand_count() as u32).collect()
    } else {
        let (lo, hi) = groom.bounds();
        crate::physics::morton::order(&groom.roots(), lo, hi)
    };
    order.resize(slots, u32::MAX);
    order
}

/// Test input shared by the lane-by-lane passes' bit-for-bit tests.
#[cfg(test)]
pub(crate) mod fixture {
    use super::{Layout, StateRow};
    use crate::groom::Groom;
    use crate::physics::lanes::{Lane, W};
    use crate::scenes::Lcg;
    use glam::Vec3;

    /// Strands of `counts` points placed at random in a unit cube (ragged: some blocks end in
    /// padding lanes), their layout under the paper's parameters, the rest state with every
    /// point moved at random (`jitter` a metre at most in x, down by at most `jitter.1` in z),
    /// and a random wetness per point.
    pub(crate) fn ragged(counts: &[u32], seed: u32, jitter: (f32, f32)) -> (Groom, Layout, Vec<StateRow>, Vec<Lane>) {
        let total: u32 = counts.iter().sum();
        let mut rng = Lcg(seed);
        let pos = (0..total)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        let groom = Groom::new(pos, counts, None, None, 1e-3).expect("groom");
        let lay = Layout::new(&groom, &crate::SimParams::paper());
        let mut state = lay.rest_state(&glam::Affine3A::IDENTITY);
        for r in &mut state {
            for l in 0..W {
                r.x.x[l] += jitter.0 * (rng.next_f32() - 0.5);
                r.x.z[l] -= jitter.1 * rng.next_f32();
            }
        }
        let wet = (0..state.len())
            .map(|_| std::array::from_fn(|_| rng.next_f32()))
            .collect();
        (groom, lay, state, wet)
    }
}
