//! Guide points as the follower output reads them: columns, guide by guide, in whole cache
//! lines.

use crate::physics::follow::GuidePoint;
use crate::physics::follow_lanes::GuideLanes;
use crate::physics::followers::GuideSpan;
use crate::physics::lanes::{Lane, L3, W};
use glam::{Vec3, Vec4};

/// Floats per cache line.
pub(super) const FLOATS_PER_LINE: usize = 16;

/// One cache line of floats, aligned as one.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub(super) struct Line(pub(super) [f32; FLOATS_PER_LINE]);

/// Guide points as columns (position x, y, z, wetness, frame x, y, z, w, rest x, y, z), guide by
/// guide: a guide's eleven columns lie together, each its points plus `W` of padding, so eight
/// consecutive points load as lanes and a guide's points are a few neighbouring cache lines
/// and one page. (Eleven planes over all guides put each guide in eleven far-apart pages:
/// followers read guides all over the groom, and the page walks cost a third of the pass.)
#[derive(Debug, Default)]
pub(super) struct GuideColumns {
    /// Whole cache lines, so that a column of a guide of 16 points is one line.
    pub(super) lines: Vec<Line>,
    /// Per guide: where its block starts in `data`.
    pub(super) base: Vec<usize>,
    /// Per guide: its points rounded up to `W` (the distance between its columns).
    pub(super) width: Vec<usize>,
    /// Per guide-groom point: its guide (for the one-point law, which names points).
    pub(super) guide_of: Vec<u32>,
    /// Per guide: its first guide-groom point.
    pub(super) first: Vec<u32>,
}

impl GuideColumns {
    /// Columns per point.
    pub(super) const PLANES: usize = 11;

    /// Laid out for guides `spans` (once; the spans of a simulation do not change).
    pub(super) fn resize(&mut self, spans: &[GuideSpan]) {
        if self.first.len() == spans.len() && spans.iter().zip(&self.first).all(|(s, &f)| s.first == f) {
            return;
        }
        self.base.clear();
        self.width.clear();
        self.guide_of.clear();
        self.first.clear();
        let mut at = 0;
        for (g, s) in spans.iter().enumerate() {
            let width = (s.count as usize).next_multiple_of(W);
            self.base.push(at);
            self.width.push(width);
            self.first.push(s.first);
            at += (Self::PLANES * width).next_multiple_of(FLOATS_PER_LINE);
            let end = (s.first + s.count) as usize;
            if self.guide_of.len() < end {
                self.guide_of.resize(end, 0);
            }
            self.guide_of[s.first as usize..end].fill(g as u32);
        }
        self.lines.clear();
        self.lines.resize(at / FLOATS_PER_LINE, Line([0.0; FLOATS_PER_LINE]));
    }

    /// The columns as floats.
    #[inline(always)]
    pub(super) fn data(&self) -> &[f32] {
        bytemuck::cast_slice(&self.lines)
    }

    /// Guide-groom point `p`, as the one-point law reads it.
    #[inline(always)]
    pub(super) fn point(&self, p: usize) -> GuidePoint {
        let g = self.guide_of[p] as usize;
        let j = p - self.first[g] as usize;
        let v = |c: usize| self.data()[self.base[g] + c * self.width[g] + j];
        (
            Vec3::new(v(0), v(1), v(2)),
            v(3),
            Vec4::new(v(4), v(5), v(6), v(7)),
            Vec3::new(v(8), v(9), v(10)),
        )
    }

    /// Guide `g`'s points `j .. j + W` (`j` a multiple of `W`; past its last point: padding,
    /// never used).
    #[inline(always)]
    pub(super) fn lanes(&self, g: usize, j: usize) -> GuideLanes {
        let (base, width, data) = (self.base[g] + j, self.width[g], self.data());
        assert!(j + W <= width && base - j + Self::PLANES * width <= data.len());
        let lane = |c: usize| -> Lane {
            let mut v = [0.0; W];
            v.copy_from_slice(&data[base + c * width..base + c * width + W]);
            v
        };
        GuideLanes {
            x: L3 {
                x: lane(0),
                y: lane(1),
                z: lane(2),
            },
            w: lane(3),
            q: [lane(4), lane(5), lane(6), lane(7)],
            r: L3 {
                x: lane(8),
                y: lane(9),
                z: lane(10),
            },
        }
    }
}
