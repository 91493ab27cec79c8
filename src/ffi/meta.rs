//! Version, result names, the last error message, and the def structs' defaults.

use super::boundary::{last_error_ptr, WetHairResult};
use super::enums::CEnum;
use super::types::{WetHairGroomDesc, WetHairSimDesc};
use std::ffi::c_char;

/// Packed library version: `major * 10000 + minor * 100 + patch` (compare with the header's
/// `WETHAIR_VERSION` to detect a header/library mismatch).
#[no_mangle]
pub extern "C" fn wethair_version() -> u32 {
    let p = |s: &str| s.parse::<u32>().unwrap_or(0);
    p(env!("CARGO_PKG_VERSION_MAJOR")) * 10000
        + p(env!("CARGO_PKG_VERSION_MINOR")) * 100
        + p(env!("CARGO_PKG_VERSION_PATCH"))
}

/// The library version as a NUL-terminated string, e.g. "0.1.0". Never NULL.
#[no_mangle]
pub extern "C" fn wethair_version_string() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr() as *const c_char
}

/// The name of a result code (a `WetHairResult` value), or "WETHAIR_RESULT_UNKNOWN". Never NULL.
#[no_mangle]
pub extern "C" fn wethair_result_string(result: u32) -> *const c_char {
    WetHairResult::from_raw(result)
        .map_or("WETHAIR_RESULT_UNKNOWN\0", WetHairResult::c_name)
        .as_ptr() as *const c_char
}

/// The message of the last failed call on this thread ("" if none). Never NULL; valid until
/// the next failing call on this thread.
#[no_mangle]
pub extern "C" fn wethair_last_error_message() -> *const c_char {
    last_error_ptr()
}

/// Fills `desc` with the 0.1.0 defaults (the paper scene's exact parameters: per-spring
/// constants, symplectic Euler) in the 0.1.0 layout, `struct_size` 128. NULL is ignored. Kept
/// for hosts built against 0.1.0; new code calls `wethair_sim_desc_init`.
///
/// # Safety
/// `desc` is NULL or points to writable memory for one `WetHairSimDesc`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_desc_default(desc: *mut WetHairSimDesc) {
    super::boundary::write_default(desc);
}

/// Fills `desc` with the defaults of the layout `struct_size` names (pass
/// `sizeof(WetHairSimDesc)`) and sets its `struct_size`. The current layout's defaults are
/// right for any groom: springs from hair-like material properties
/// (`WETHAIR_SPRING_MODEL_MATERIAL`) and the AUTO integrator; an older layout's size gets that
/// release's defaults. Returns `WETHAIR_ERROR_NULL_POINTER` or `WETHAIR_ERROR_STRUCT_SIZE`
/// (nothing written) on bad input.
///
/// # Safety
/// `desc` is NULL or points to `struct_size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_desc_init(desc: *mut WetHairSimDesc, struct_size: u32) -> WetHairResult {
    boundary!({
        let v = if struct_size as usize == std::mem::size_of::<WetHairSimDesc>() {
            WetHairSimDesc::current_values()
        } else {
            WetHairSimDesc::default_values()
        };
        super::boundary::write_sized(desc, struct_size, v, "desc")
    })
}

/// Fills `desc` with empty arrays, 1 g per point, and its `struct_size`. NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable memory for one `WetHairGroomDesc`.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_desc_default(desc: *mut WetHairGroomDesc) {
    super::boundary::write_default(desc);
}

/// Fills `desc` with the load defaults (the file's units and axes, 1 g per metre of strand,
/// segments under 0.1 mm welded) and its `struct_size`. NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable memory for one `WetHairLoadDesc`.
#[no_mangle]
pub unsafe extern "C" fn wethair_load_desc_default(desc: *mut super::types::WetHairLoadDesc) {
    super::boundary::write_default(desc);
}
