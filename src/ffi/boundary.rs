//! The panic and error boundary every `extern "C"` body goes through: result codes, the
//! per-thread error message, and the guard macros.

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::CString;

/// Result of every fallible C call.
#[repr(u32)]
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WetHairResult {
    /// Success.
    WETHAIR_OK = 0,
    /// A required pointer was NULL.
    WETHAIR_ERROR_NULL_POINTER = 1,
    /// A value was out of range: NaN, inf, negative, zero, or an unknown enum value.
    WETHAIR_ERROR_INVALID_ARGUMENT = 2,
    /// A struct's `struct_size` is not one this library knows.
    WETHAIR_ERROR_STRUCT_SIZE = 3,
    /// A count exceeds a documented capacity.
    WETHAIR_ERROR_CAPACITY = 4,
    /// The output buffer is too small; nothing was written.
    WETHAIR_ERROR_BUFFER_TOO_SMALL = 5,
    /// A file could not be read.
    WETHAIR_ERROR_IO = 6,
    /// A groom file is truncated or malformed.
    WETHAIR_ERROR_PARSE = 7,
    /// A step produced a non-finite value; the simulation keeps failing until reset.
    WETHAIR_ERROR_UNSTABLE = 8,
    /// An internal panic was caught at the boundary; destroy the object involved.
    WETHAIR_ERROR_PANIC = 9,
    /// The GPU device failed (lost, out of memory, validation); destroy the simulation.
    WETHAIR_ERROR_DEVICE = 10,
    /// The request is not available here: no GPU adapter for the GPU backend, or an
    /// integrator the chosen backend does not run.
    WETHAIR_ERROR_UNSUPPORTED = 11,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Stores `msg` as this thread's last error message.
pub(crate) fn set_last_error(msg: &str) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Pointer to this thread's last error message (valid until the next failing call here).
pub(crate) fn last_error_ptr() -> *const std::ffi::c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// A failure on its way out: the code and the message to store.
pub(crate) struct Fail(pub WetHairResult, pub String);

impl From<Error> for Fail {
    fn from(e: Error) -> Fail {
        let code = match &e {
            Error::InvalidArgument(_) => WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
            Error::Capacity(_) => WetHairResult::WETHAIR_ERROR_CAPACITY,
            Error::Io(_) => WetHairResult::WETHAIR_ERROR_IO,
            Error::Parse(_) => WetHairResult::WETHAIR_ERROR_PARSE,
            Error::Unstable { .. } => WetHairResult::WETHAIR_ERROR_UNSTABLE,
            Error::Device(_) => WetHairResult::WETHAIR_ERROR_DEVICE,
            Error::Unsupported(_) => WetHairResult::WETHAIR_ERROR_UNSUPPORTED,
        };
        Fail(code, e.to_string())
    }
}

/// The boundary around every fallible `extern "C"` body: `boundary!({ ... })` runs the block
/// (which returns `Result<(), Fail>`) under [`guard`], named after the function it sits in, so
/// no call site types its own name (a nested item's type name carries its enclosing function's
/// path).
macro_rules! boundary {
    ($body:block) => {{
        fn here() {}
        let name = $crate::ffi::boundary::enclosing_fn(std::any::type_name_of_val(&here));
        $crate::ffi::boundary::guard(name, || $body)
    }};
}

/// `"crate::ffi::sim::wethair_sim_step::here"` → `"wethair_sim_step"`.
pub(crate) fn enclosing_fn(here: &'static str) -> &'static str {
    let path = here.strip_suffix("::here").unwrap_or(here);
    path.rsplit("::").next().unwrap_or(path)
}

/// Runs `body` under `catch_unwind`; maps its error or panic to a code and a message.
pub(crate) fn guard(name: &str, body: impl FnOnce() -> Result<(), Fail>) -> WetHairResult {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)) {
        Ok(Ok(())) => WetHairResult::WETHAIR_OK,
        Ok(Err(Fail(code, msg))) => {
            set_last_error(&format!("{name}: {msg}"));
            code
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_last_error(&format!("{name}: internal panic: {what}"));
            WetHairResult::WETHAIR_ERROR_PANIC
        }
    }
}

/// The failure for a NULL pointer named `name`.
pub(crate) fn null(name: &str) -> Fail {
    Fail(WetHairResult::WETHAIR_ERROR_NULL_POINTER, format!("{name} is NULL"))
}

/// Checks a def or output struct: not NULL, and its leading `struct_size` (read alone first,
/// so a smaller struct from an older host is never over-read) is this library's size of `T`.
pub(crate) fn check_struct<T>(p: *const T, name: &str) -> Result<(), Fail> {
    if p.is_null() {
        return Err(null(name));
    }
    // SAFETY: p is non-NULL and, per the API, points to at least a u32 struct_size.
    let size = unsafe { std::ptr::read_unaligned(p as *const u32) } as usize;
    let want = std::mem::size_of::<T>();
    if size != want {
        let ty = std::any::type_name::<T>().rsplit("::").next().unwrap_or("the struct");
        return Err(Fail(
            WetHairResult::WETHAIR_ERROR_STRUCT_SIZE,
            format!("{name}->struct_size is {size}, this library expects {want} (sizeof({ty}))"),
        ));
    }
    Ok(())
}

/// Turns a nullable pointer into a reference, or fails with `WETHAIR_ERROR_NULL_POINTER`.
macro_rules! nonnull {
    ($p:expr, $name:literal) => {
        match unsafe { $p.as_ref() } {
            Some(r) => r,
            None => return Err($crate::ffi::boundary::null($name)),
        }
    };
}

/// Like `nonnull!` for a mutable pointer.
macro_rules! nonnull_mut {
    ($p:expr, $name:literal) => {
        match unsafe { $p.as_mut() } {
            Some(r) => r,
            None => return Err($crate::ffi::boundary::null($name)),
        }
    };
}

/// Reads a def struct behind a pointer after [`check_struct`].
macro_rules! read_def {
    ($p:expr, $ty:ty, $name:literal) => {{
        let p: *const $ty = $p;
        $crate::ffi::boundary::check_struct(p, $name)?;
        unsafe { &*p }
    }};
}

/// Checks an output struct (the host sets `struct_size`; it is written only on success).
macro_rules! check_out_size {
    ($p:expr, $ty:ty, $name:literal) => {{
        let p: *mut $ty = $p;
        $crate::ffi::boundary::check_struct(p as *const $ty, $name)?;
        p
    }};
}
