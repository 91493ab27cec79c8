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

/// A C struct that leads with a `u32 struct_size`. The ABI only grows: a host compiled
/// against an older header passes its older, smaller size, so every size from `FIRST_SIZE`
/// (the layout of the first release that had the struct) up to today's is accepted. A def
/// struct's fields past the host's size take their defaults; an output struct is written only
/// up to the host's size. Larger sizes (a newer header than this library) are refused.
///
/// # Safety
/// The type is `#[repr(C)]`, starts with `struct_size: u32`, and any bytes are valid for it
/// once its leading `FIRST_SIZE` bytes are (pointers may be NULL, enums are `u32` fields).
pub(crate) unsafe trait SizedStruct: Copy {
    /// `sizeof` in the first release that had the struct (0.1.0 for the first structs).
    const FIRST_SIZE: usize;
}

/// A def struct: one the host fills (after `..._default()`) and passes in.
pub(crate) trait DefStruct: SizedStruct {
    /// The values `..._default()` writes; a shorter struct's missing fields take them.
    fn defaults() -> Self;
}

/// Checks a def or output struct: not NULL, and its leading `struct_size` (read alone first,
/// so a smaller struct from an older host is never over-read) within
/// `FIRST_SIZE..=size_of::<T>()`. Returns the host's size.
pub(crate) fn check_struct<T: SizedStruct>(p: *const T, name: &str) -> Result<usize, Fail> {
    if p.is_null() {
        return Err(null(name));
    }
    // SAFETY: p is non-NULL and, per the API, points to at least a u32 struct_size.
    let size = unsafe { std::ptr::read_unaligned(p as *const u32) } as usize;
    let (first, now) = (T::FIRST_SIZE, std::mem::size_of::<T>());
    if !(first..=now).contains(&size) {
        let ty = std::any::type_name::<T>().rsplit("::").next().unwrap_or("the struct");
        let accepted = if first == now {
            format!("{now}")
        } else {
            format!("{first}..={now}")
        };
        return Err(Fail(
            WetHairResult::WETHAIR_ERROR_STRUCT_SIZE,
            format!("{name}->struct_size is {size}; this library accepts sizeof({ty}) of {accepted}"),
        ));
    }
    Ok(size)
}

/// Reads a def struct of the host's size over the defaults (see [`SizedStruct`]).
pub(crate) fn read_def<T: DefStruct>(p: *const T, name: &str) -> Result<T, Fail> {
    let size = check_struct(p, name)?;
    let mut v = T::defaults();
    // SAFETY: the host's struct holds `size` bytes (its struct_size), `v` holds at least that
    // many (checked above), and any bytes are valid for T (SizedStruct's contract).
    unsafe { std::ptr::copy_nonoverlapping(p as *const u8, &mut v as *mut T as *mut u8, size) };
    Ok(v)
}

/// What every `..._default(p)` does: writes `T`'s defaults in its *first released* layout
/// (`FIRST_SIZE` bytes, `struct_size` set to it), so a host built against that header is never
/// written past its struct. A struct that grows gets a sized default function with its new
/// fields. NULL is ignored.
pub(crate) fn write_default<T: DefStruct>(p: *mut T) {
    if !p.is_null() {
        Out {
            ptr: p,
            size: T::FIRST_SIZE,
        }
        .write(T::defaults());
    }
}

/// What every `..._init(p, size)` does: checks `size` as [`check_struct`] checks a
/// `struct_size`, then writes `v`'s first `size` bytes with `struct_size` set to `size`.
pub(crate) fn write_sized<T: SizedStruct>(p: *mut T, size: u32, v: T, name: &str) -> Result<(), Fail> {
    if p.is_null() {
        return Err(null(name));
    }
    let probe = size;
    check_struct(&probe as *const u32 as *const T, name)?;
    Out {
        ptr: p,
        size: size as usize,
    }
    .write(v);
    Ok(())
}

/// An output struct checked by [`check_struct`]: written only on success, only up to the
/// host's size, with `struct_size` left at the host's size.
pub(crate) struct Out<T> {
    ptr: *mut T,
    size: usize,
}

impl<T: SizedStruct> Out<T> {
    /// Checks `p` as an output of type `T`.
    pub(crate) fn new(p: *mut T, name: &str) -> Result<Self, Fail> {
        let size = check_struct(p as *const T, name)?;
        Ok(Out { ptr: p, size })
    }

    /// Writes the first `size` bytes of `v`, its `struct_size` set to the host's.
    pub(crate) fn write(self, mut v: T) {
        // SAFETY: every SizedStruct starts with a u32 struct_size; the host's struct holds
        // `size` bytes, and `v` at least as many.
        unsafe {
            (&mut v as *mut T as *mut u32).write(self.size as u32);
            std::ptr::copy_nonoverlapping(&v as *const T as *const u8, self.ptr as *mut u8, self.size);
        }
    }
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

/// Reads a def struct behind a pointer (an owned copy; see [`read_def`]).
macro_rules! read_def {
    ($p:expr, $ty:ty, $name:literal) => {{
        let p: *const $ty = $p;
        $crate::ffi::boundary::read_def::<$ty>(p, $name)?
    }};
}

/// Checks an output struct (the host sets `struct_size`; it is written only on success).
macro_rules! check_out_size {
    ($p:expr, $ty:ty, $name:literal) => {{
        let p: *mut $ty = $p;
        $crate::ffi::boundary::Out::<$ty>::new(p, $name)?
    }};
}
