//! Skinned roots on the CPU (`physics/roots.rs`): each slot's root frames at the start and the
//! end of the next step, and each row's pinned offset from its strand's root, from which the
//! block kernel places pinned points substep by substep. Nothing here exists without skinned
//! roots.

use super::layout::{Layout, StateRow};
use crate::physics::lanes::{L3, W};
use crate::physics::roots::{root_between, RootFrame};

/// The root frames per slot (`block * W + lane`) and the pinned offsets per row.
#[derive(Debug)]
pub(super) struct Roots {
    from: Vec<RootFrame>,
    to: Vec<RootFrame>,
    /// Per row: each lane's rest position minus its strand's root's (head space).
    offset: Vec<L3>,
}

impl Roots {
    /// Every root at rest (where the layout's rest pose puts it under the identity head).
    pub(super) fn new(lay: &Layout) -> Roots {
        let mut offset = vec![L3::ZERO; lay.rest_local.len()];
        let mut at_rest = vec![RootFrame::at_rest(glam::Vec3::ZERO); lay.blocks * W];
        for b in 0..lay.blocks {
            let root = lay.rest_local[b * lay.rows];
            for l in 0..W {
                at_rest[b * W + l] = RootFrame::at_rest(root.get(l));
            }
            for i in 0..lay.rows {
                let r = &lay.rest_local[b * lay.rows + i];
                for l in 0..W {
                    offset[b * lay.rows + i].set(l, r.get(l) - root.get(l));
                }
            }
        }
        Roots {
            from: at_rest.clone(),
            to: at_rest,
            offset,
        }
    }

    /// Moves the roots from `from` to `to` (one per host strand) over the next step.
    pub(super) fn place(&mut self, lay: &Layout, from: &[RootFrame], to: &[RootFrame]) {
        for (s, (f, t)) in from.iter().zip(to).enumerate() {
            let slot = lay.slot_of_strand[s] as usize;
            self.from[slot] = *f;
            self.to[slot] = *t;
        }
    }

    /// Where row `i` of block `b`'s pinned lanes go at the end of a substep `a` of the way
    /// through the step.
    #[inline]
    pub(super) fn target(&self, rows: usize, b: usize, i: usize, a: f32) -> L3 {
        let off = &self.offset[b * rows + i];
        let mut t = L3::ZERO;
        for l in 0..W {
            let f = root_between(&self.from[b * W + l], &self.to[b * W + l], a);
            t.set(l, f.place(off.get(l)));
        }
        t
    }

    /// Carries host strands `strands` rigidly from `from` to `to` (one each), at rest.
    pub(super) fn carry(lay: &Layout, state: &mut [StateRow], strands: &[u32], from: &[RootFrame], to: &[RootFrame]) {
        for ((&s, f), t) in strands.iter().zip(from).zip(to) {
            let (b, l) = lay.lane_of(s as usize);
            for row in &mut state[b * lay.rows..b * lay.rows + lay.strand_points(s as usize)] {
                row.x.set(l, f.carry(t, row.x.get(l)));
                row.v.set(l, glam::Vec3::ZERO);
            }
        }
    }
}
