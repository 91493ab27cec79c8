//! Asking the cache for memory a pass will read soon. A hint only: it reads nothing, cannot
//! fault, and changes no result; where the target has no prefetch instruction it does
//! nothing.

/// Bytes in a cache line.
const LINE: usize = 64;

/// Asks for the line holding `p` (any address, valid or not).
#[inline(always)]
pub fn line<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: a prefetch is a hint; it reads nothing and cannot fault.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p as *const i8) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Asks for every line `items` spans.
#[inline(always)]
pub fn lines<T>(items: &[T]) {
    let (start, bytes) = (items.as_ptr() as *const u8, std::mem::size_of_val(items));
    if bytes == 0 {
        return;
    }
    // One address a line from the first byte on, and the last byte (whose line a start
    // partway into a line could leave out).
    for off in (0..bytes).step_by(LINE) {
        line(start.wrapping_add(off));
    }
    line(start.wrapping_add(bytes - 1));
}
