//! Which particles each block's list entries touch: a block's reactions (or absorption demands)
//! sit in its chunk's list as one run, and beside it the lowest and highest particle slot the
//! run names. A task that handles a range of particles reads only the runs that meet its range,
//! in list order, so what it sums per particle is what one thread summing every list would, in
//! the same order. Cells are numbered along x first and a block's particles sit in a few
//! neighbouring cells, so most runs meet one task's range.

use std::ops::Range;

/// The slots one block's run of a list touches: the run ends at `end` and all its slots lie
/// in `lo..=hi`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlotSpan {
    /// One past the run's last entry, in its list.
    pub end: u32,
    /// Lowest slot in the run.
    pub lo: u32,
    /// Highest slot in the run.
    pub hi: u32,
}

impl SlotSpan {
    /// The span of the run whose entries have `slots` and which ends at `end` (what a block
    /// just added to its chunk's list), or `None` when the run is empty.
    pub fn of(mut slots: impl Iterator<Item = u32>, end: usize) -> Option<SlotSpan> {
        let first = slots.next()?;
        let (lo, hi) = slots.fold((first, first), |(lo, hi), s| (lo.min(s), hi.max(s)));
        Some(SlotSpan {
            end: end as u32,
            lo,
            hi,
        })
    }

    /// Whether any slot of the run may lie in `range`.
    #[inline(always)]
    fn meets(&self, range: &Range<u32>) -> bool {
        self.hi >= range.start && self.lo < range.end
    }
}

/// Calls `f` on every entry of `lists` whose slot (`slot_of`) lies in `range`, list by list and
/// in each list's order, skipping the runs whose spans miss the range. Each list's spans cover
/// it in order.
#[inline(always)]
pub fn for_each_in_range<'a, T: 'a>(
    lists: impl Iterator<Item = (&'a [T], &'a [SlotSpan])>,
    range: Range<u32>,
    slot_of: impl Fn(&T) -> u32,
    mut f: impl FnMut(&T),
) {
    for (list, spans) in lists {
        debug_assert_eq!(spans.last().map_or(0, |s| s.end as usize), list.len());
        let mut from = 0;
        for span in spans {
            let to = span.end as usize;
            if span.meets(&range) {
                for e in &list[from..to] {
                    if range.contains(&slot_of(e)) {
                        f(e);
                    }
                }
            }
            from = to;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{for_each_in_range, SlotSpan};

    /// A block's span is the slots it added, ending where its list ends; a block that added
    /// none has no span.
    #[test]
    fn a_span_bounds_the_slots_a_block_added() {
        let list = [90u32, 7, 12, 40, 9];
        assert_eq!(SlotSpan::of(list[5..].iter().copied(), 5), None);
        assert_eq!(
            SlotSpan::of(list[2..].iter().copied(), 5),
            Some(SlotSpan { end: 5, lo: 9, hi: 40 })
        );
        assert_eq!(
            SlotSpan::of(list.iter().copied(), 5),
            Some(SlotSpan { end: 5, lo: 7, hi: 90 })
        );
    }

    /// Ranges that cover the slots between them visit every entry once, each range its own
    /// entries in list order: what one pass over every list would visit.
    #[test]
    fn ranges_visit_each_entry_once_in_list_order() {
        // Two lists of three blocks each (one block empty), slots 0..40.
        let a = [3u32, 5, 4, 30, 31, 12];
        let b = [20u32, 39, 1, 2];
        let sa = [
            SlotSpan::of(a[..3].iter().copied(), 3).unwrap(),
            SlotSpan::of(a[3..].iter().copied(), 6).unwrap(),
        ];
        let sb = [
            SlotSpan::of(b[..2].iter().copied(), 2).unwrap(),
            SlotSpan::of(b[2..].iter().copied(), 4).unwrap(),
        ];
        let lists = || [(&a[..], &sa[..]), (&b[..], &sb[..])].into_iter();
        let all: Vec<u32> = a.iter().chain(&b).copied().collect();
        for cut in [0u32, 1, 4, 13, 25, 40] {
            let mut seen = Vec::new();
            for range in [0..cut, cut..40] {
                let mut mine = Vec::new();
                for_each_in_range(lists(), range.clone(), |&s| s, |&s| mine.push(s));
                let expected: Vec<u32> = all.iter().copied().filter(|s| range.contains(s)).collect();
                assert_eq!(mine, expected, "range {range:?}");
                seen.extend(mine);
            }
            seen.sort();
            let mut every = all.clone();
            every.sort();
            assert_eq!(seen, every);
        }
    }
}
