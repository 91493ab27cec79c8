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

/// Fills `desc` with the defaults (the paper scene's parameters) and its `struct_size`.
/// NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable memory for one `WetHairSimDesc`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_desc_default(desc: *mut WetHairSimDesc) {
    if !desc.is_null() {
        desc.write(WetHairSimDesc::default_values());
    }
}

/// Fills `desc` with empty arrays, 1 g per point, and its `struct_size`. NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable memory for one `WetHairGroomDesc`.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_desc_default(desc: *mut WetHairGroomDesc) {
    if !desc.is_null() {
        desc.write(WetHairGroomDesc {
            struct_size: std::mem::size_of::<WetHairGroomDesc>() as u32,
            strand_count: 0,
            strand_point_counts: std::ptr::null(),
            positions: std::ptr::null(),
            point_count: 0,
            pinned: std::ptr::null(),
            masses: std::ptr::null(),
            default_mass: 1.0e-3,
        });
    }
}
