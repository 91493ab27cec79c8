//! `WetHairGroom`: strands from the host's arrays, the paper scene, or a file.

use super::boundary::{Fail, WetHairResult};
use super::types::{WetHairGroomDesc, WetHairLoadDesc};
use crate::groom::{self, Groom, MAX_POINTS, MAX_STRANDS};
use glam::Vec3;
use std::ffi::{c_char, CStr};

/// Opaque strand set; create with `wethair_groom_*`, free with `wethair_groom_destroy`.
pub struct WetHairGroom(pub(crate) Groom, std::ffi::CString);

fn publish(g: Groom, out: *mut *mut WetHairGroom) {
    // The report's message has no NUL bytes (it is made of numbers and ASCII words).
    let msg = std::ffi::CString::new(g.load_report().message()).unwrap_or_default();
    unsafe { out.write(Box::into_raw(Box::new(WetHairGroom(g, msg)))) };
}

/// Creates a groom from the host's strands (see `WetHairGroomDesc`).
///
/// # Safety
/// `desc`'s arrays hold the counts they claim; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_create(
    desc: *const WetHairGroomDesc,
    out: *mut *mut WetHairGroom,
) -> WetHairResult {
    boundary!({
        let d = read_def!(desc, WetHairGroomDesc, "desc");
        if out.is_null() {
            return Err(super::boundary::null("out"));
        }
        let (ns, np) = (d.strand_count as usize, d.point_count as usize);
        if ns > MAX_STRANDS || np > MAX_POINTS {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_CAPACITY,
                format!("{ns} strands / {np} points exceed {MAX_STRANDS} / {MAX_POINTS}"),
            ));
        }
        if d.strand_point_counts.is_null() || d.positions.is_null() {
            return Err(super::boundary::null("strand_point_counts or positions"));
        }
        let counts = std::slice::from_raw_parts(d.strand_point_counts, ns);
        let xyz = std::slice::from_raw_parts(d.positions, np * 3);
        let positions = xyz.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
        let pinned = (!d.pinned.is_null()).then(|| {
            std::slice::from_raw_parts(d.pinned, np)
                .iter()
                .map(|&b| b != 0)
                .collect()
        });
        let masses = (!d.masses.is_null()).then(|| std::slice::from_raw_parts(d.masses, np).to_vec());
        crate::error::check_positive("default_mass", d.default_mass)?;
        let g = Groom::new(positions, counts, pinned, masses, d.default_mass)?;
        publish(g, out);
        Ok(())
    })
}

/// Creates the paper scene: `strands` strands of `points` points on a 0.1 m head (see README).
///
/// # Safety
/// `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_create_paper_scene(
    strands: u32,
    points: u32,
    out: *mut *mut WetHairGroom,
) -> WetHairResult {
    boundary!({
        if out.is_null() {
            return Err(super::boundary::null("out"));
        }
        if strands as usize > MAX_STRANDS || (strands as usize).saturating_mul(points as usize) > MAX_POINTS {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_CAPACITY,
                format!("{strands} x {points} exceeds the groom capacity"),
            ));
        }
        publish(groom::paper_scene(strands, points)?, out);
        Ok(())
    })
}

/// Loads a groom file in its own units and axes; every point gets `point_mass` kg. Reads
/// TressFX `.tfx` (3.x and 4.x), Cem Yuksel `.hair` and USC-HairSalon `.data` files. For
/// units, up axis, masses by length, subsampling or resampling use
/// `wethair_groom_load_with_desc`.
///
/// # Safety
/// `path` is a NUL-terminated string; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_load(
    path: *const c_char,
    point_mass: f32,
    out: *mut *mut WetHairGroom,
) -> WetHairResult {
    boundary!({
        if path.is_null() || out.is_null() {
            return Err(super::boundary::null("path or out"));
        }
        crate::error::check_positive("point_mass", point_mass)?;
        let p = utf8_path(path)?;
        publish(groom::load_file(std::path::Path::new(p), point_mass)?, out);
        Ok(())
    })
}

/// Loads a groom file as `wethair_groom_load` does, then applies `desc` (see
/// `WetHairLoadDesc`): scale to metres, up axis, point masses, every Nth strand, resampling.
///
/// # Safety
/// `path` is a NUL-terminated string; `desc` was filled by `wethair_load_desc_default`; `out`
/// is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_load_with_desc(
    path: *const c_char,
    desc: *const WetHairLoadDesc,
    out: *mut *mut WetHairGroom,
) -> WetHairResult {
    boundary!({
        let d = read_def!(desc, WetHairLoadDesc, "desc");
        if path.is_null() || out.is_null() {
            return Err(super::boundary::null("path or out"));
        }
        let options = d.options()?;
        let p = utf8_path(path)?;
        publish(groom::load_file_with(std::path::Path::new(p), &options)?, out);
        Ok(())
    })
}

/// What loading welded or dropped, as one NUL-terminated line ("" when nothing was, or when
/// the groom was not loaded by `wethair_groom_load_with_desc`), or NULL when `groom` is NULL.
/// Valid until the groom is destroyed.
///
/// # Safety
/// `groom` is NULL or came from `wethair_groom_*`.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_get_load_message(groom: *const WetHairGroom) -> *const c_char {
    match groom.as_ref() {
        Some(g) => g.1.as_ptr(),
        None => std::ptr::null(),
    }
}

/// A C path as UTF-8, or `WETHAIR_ERROR_INVALID_ARGUMENT`.
unsafe fn utf8_path<'a>(path: *const c_char) -> Result<&'a str, Fail> {
    CStr::from_ptr(path).to_str().map_err(|_| {
        Fail(
            WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
            "path is not UTF-8".into(),
        )
    })
}

/// Reports a groom's strand and point counts (either output may be NULL).
///
/// # Safety
/// `groom` came from `wethair_groom_*`; outputs are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_get_counts(
    groom: *const WetHairGroom,
    strands: *mut u32,
    points: *mut u32,
) -> WetHairResult {
    boundary!({
        let g = nonnull!(groom, "groom");
        if let Some(s) = strands.as_mut() {
            *s = g.0.strand_count() as u32;
        }
        if let Some(p) = points.as_mut() {
            *p = g.0.point_count() as u32;
        }
        Ok(())
    })
}

/// Frees a groom. NULL is ignored. Simulations created from it are unaffected.
///
/// # Safety
/// `groom` came from `wethair_groom_*` and is not used again.
#[no_mangle]
pub unsafe extern "C" fn wethair_groom_destroy(groom: *mut WetHairGroom) {
    if !groom.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(Box::from_raw(groom))));
    }
}
