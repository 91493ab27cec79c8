//! Counting sort by an integer key, the one way both grids order their points into cells: the
//! water's dense grid (`grid.rs`, keys are cell indices) and the hair's hashed grid
//! (`hash_grid.rs`, keys are buckets). Stable (item order within a key), so the lists, and
//! what is summed over them, do not depend on anything but the input.

/// The items ordered by key: those with key `k` are `sorted[start[k]..start[k + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct CountingSort {
    /// Per key, where its items begin in `sorted`; `start[keys]` is the item count.
    pub start: Vec<u32>,
    /// Item indices in key order.
    pub sorted: Vec<u32>,
}

impl CountingSort {
    /// Empty, with room for `keys` keys and `items` items.
    pub fn with_capacity(keys: usize, items: usize) -> CountingSort {
        CountingSort {
            start: Vec::with_capacity(keys + 1),
            sorted: Vec::with_capacity(items),
        }
    }

    /// Orders items `0..keys.len()` by `keys` (each below `n_keys`). Counts, prefix-sums,
    /// then scatters through `start` used as the cursors, which end one key ahead and are
    /// shifted back: no second array.
    pub fn sort(&mut self, keys: &[u32], n_keys: usize) {
        self.start.clear();
        self.start.resize(n_keys + 1, 0);
        for &k in keys {
            self.start[k as usize + 1] += 1;
        }
        // The running sum stays in a register: reading back the element just written made
        // each step wait on a store (a quarter of the water grid's build with 1,000 particles).
        let mut sum = 0u32;
        for c in &mut self.start {
            sum += *c;
            *c = sum;
        }
        self.sorted.clear();
        self.sorted.resize(keys.len(), 0);
        for (i, &k) in keys.iter().enumerate() {
            let at = &mut self.start[k as usize];
            self.sorted[*at as usize] = i as u32;
            *at += 1;
        }
        self.start.copy_within(0..n_keys, 1);
        self.start[0] = 0;
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        4 * (self.start.capacity() + self.sorted.capacity())
    }
}
