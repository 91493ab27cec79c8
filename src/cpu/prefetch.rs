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
    span(items.as_ptr() as *const u8, std::mem::size_of_val(items));
}

/// Asks for every line of the `bytes` bytes from `start` (any address: nothing is read).
#[inline(always)]
fn span(start: *const u8, bytes: usize) {
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

/// Asks for what block `b`'s substep reads first, whose `rows` state rows start at `state`:
/// the state, the rows' parameters and its pinned rows' rest positions.
#[inline(always)]
pub(super) fn next_block(ctx: &super::kernel::Ctx, b: usize, state: *const super::layout::StateRow, rows: usize) {
    let row = b * rows;
    span(
        state as *const u8,
        rows * std::mem::size_of::<super::layout::StateRow>(),
    );
    lines(&ctx.params[row..row + rows]);
    for r in (row..row + rows).filter(|&r| ctx.lay.pinned_row[r]) {
        lines(std::slice::from_ref(&ctx.lay.rest_local[r]));
    }
}
