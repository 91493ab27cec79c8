//! A vector of 32-byte rows (a row of eight `f32` or `u32` lanes) that starts on a 32-byte
//! boundary, so that every row lies in one cache line.
//!
//! A `Vec<[f32; 8]>` is only as aligned as `f32`, and the allocator hands a large one out
//! 16 bytes past a line's start: every row then straddles two lines, and each row the
//! kernel touches at random (the wetness of a row near a drop, its held water and capacity)
//! costs two cache misses instead of one. The rows are stored as an aligned wrapper and
//! seen as the plain rows through `Deref`, so every law keeps taking `&[[f32; 8]]`.

use std::ops::{Deref, DerefMut};

/// One row, on a 32-byte boundary. Holds only rows of exactly 32 bytes (checked at compile
/// time where a vector of them is made), so it has no padding and a slice of it is a slice
/// of the rows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
struct Aligned<T>(T);

/// Rows of 32 bytes, each in one cache line. Derefs to `[T]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AlignedRows<T: Copy>(Vec<Aligned<T>>);

impl<T: Copy> AlignedRows<T> {
    /// A row is 32 bytes, the wrapper's alignment: the wrapper adds no padding.
    const ROW: () = assert!(std::mem::size_of::<T>() == 32 && std::mem::size_of::<Aligned<T>>() == 32);

    /// `n` copies of `row`.
    pub fn filled(row: T, n: usize) -> Self {
        let () = Self::ROW;
        AlignedRows(vec![Aligned(row); n])
    }

    /// Rows allocated (for the memory report).
    pub fn capacity(&self) -> usize {
        self.0.capacity()
    }
}

impl<T: Copy> Deref for AlignedRows<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        let () = Self::ROW;
        // SAFETY: `Aligned<T>` is `repr(C)` around one `T` and, by `ROW`, the same size, so
        // `n` of them are `n` `T`s laid end to end, and their alignment is at least `T`'s.
        unsafe { std::slice::from_raw_parts(self.0.as_ptr().cast::<T>(), self.0.len()) }
    }
}

impl<T: Copy> DerefMut for AlignedRows<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        let () = Self::ROW;
        // SAFETY: as in `deref`, and the borrow is unique.
        unsafe { std::slice::from_raw_parts_mut(self.0.as_mut_ptr().cast::<T>(), self.0.len()) }
    }
}

impl<'a, T: Copy> IntoIterator for &'a AlignedRows<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a, T: Copy> IntoIterator for &'a mut AlignedRows<T> {
    type Item = &'a mut T;
    type IntoIter = std::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::AlignedRows;

    #[test]
    fn every_row_lies_in_one_cache_line() {
        for n in [1usize, 7, 1000, 100_000] {
            let mut rows = AlignedRows::filled([0.0f32; 8], n);
            assert_eq!(rows.len(), n);
            assert_eq!(rows.as_ptr() as usize % 32, 0, "{n} rows start on a 32-byte boundary");
            rows[n - 1][7] = 1.0;
            assert_eq!(rows.iter().map(|r| r.iter().sum::<f32>()).sum::<f32>(), 1.0);
            let u = AlignedRows::filled([3u32; 8], n);
            assert_eq!(u.as_ptr() as usize % 32, 0);
            assert!(u.iter().all(|r| *r == [3; 8]));
        }
    }
}
