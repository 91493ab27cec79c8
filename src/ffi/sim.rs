//! `WetHairSim`: create, drive (head, water, step, reset), and read out (vertices, stats).

use super::boundary::{Fail, WetHairResult};
use super::groom::WetHairGroom;
use super::types::{WetHairAdvance, WetHairBackendInfo, WetHairSimDesc, WetHairStats, WetHairVertexLayout};
use crate::params::{VertexAttributes, MAX_WATER_CAPACITY};
use crate::physics::roots::RootFrame;
use crate::sim::Simulation;
use glam::{Mat4, Vec3};

/// Opaque simulation; create with `wethair_sim_create`, free with `wethair_sim_destroy`.
pub struct WetHairSim(pub(crate) Simulation);

/// Creates a simulation from `desc` (its groom is copied).
///
/// # Safety
/// `desc` points to a `WetHairSimDesc` filled by `wethair_sim_desc_default`; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_create(desc: *const WetHairSimDesc, out: *mut *mut WetHairSim) -> WetHairResult {
    boundary!({
        let d = read_def!(desc, WetHairSimDesc, "desc");
        if out.is_null() {
            return Err(super::boundary::null("out"));
        }
        let groom: &WetHairGroom = nonnull!(d.groom, "desc->groom");
        let params = d.params()?;
        let sim = Simulation::new(&groom.0, params)?;
        out.write(Box::into_raw(Box::new(WetHairSim(sim))));
        Ok(())
    })
}

/// Frees a simulation and joins its worker threads. NULL is ignored.
///
/// # Safety
/// `sim` came from `wethair_sim_create` and is not used again.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_destroy(sim: *mut WetHairSim) {
    if !sim.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(Box::from_raw(sim))));
    }
}

/// The column-major 4×4 a host passes as `matrix` (16 floats, read unaligned), or the NULL
/// pointer error. What it may hold is checked by the call it is for.
///
/// # Safety
/// `matrix` is NULL or points to 16 floats.
unsafe fn matrix_arg(matrix: *const f32) -> Result<Mat4, Fail> {
    if matrix.is_null() {
        return Err(super::boundary::null("matrix"));
    }
    let m: [f32; 16] = std::ptr::read_unaligned(matrix as *const [f32; 16]);
    Ok(Mat4::from_cols_array(&m))
}

/// Sets the head transform reached at the end of the next step: a column-major 4×4 affine
/// matrix without reflection (16 floats). Pinned points and colliders follow it.
///
/// # Safety
/// `sim` is valid; `matrix` is NULL or points to 16 floats.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_head_transform(sim: *mut WetHairSim, matrix: *const f32) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let m = matrix_arg(matrix)?;
        s.0.set_head_transform(m)?;
        Ok(())
    })
}

/// Sets where SDF collider `index` (of `WetHairSimDesc::sdfs`) is at the end of the next
/// step: its grid frame to the world, a column-major 4×4 of a rotation, a translation and a
/// uniform scale (16 floats). It moves there over the step's substeps, as the head does.
///
/// # Safety
/// `sim` is valid; `matrix` is NULL or points to 16 floats.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_sdf_transform(
    sim: *mut WetHairSim,
    index: u32,
    matrix: *const f32,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let m = matrix_arg(matrix)?;
        s.0.set_sdf_transform(index as usize, m)?;
        Ok(())
    })
}

/// Sets where collider `index`'s own frame (of `WetHairSimDesc::collider_frames`) is at the
/// end of the next step: the frame to the world, a column-major 4×4 of a rotation, a
/// translation and a uniform scale (16 floats). It moves there over the step's substeps, as
/// the head does. A simulation whose colliders follow the head (no `collider_frames`) gets
/// `WETHAIR_ERROR_UNSUPPORTED`.
///
/// # Safety
/// `sim` is valid; `matrix` is NULL or points to 16 floats.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_collider_transform(
    sim: *mut WetHairSim,
    index: u32,
    matrix: *const f32,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let m = matrix_arg(matrix)?;
        s.0.set_collider_transform(index as usize, m)?;
        Ok(())
    })
}

/// Simulates the first `fraction` of the guides, (0, 1], from the next step on (a simulation
/// made with `WetHairSimDesc::guides`; others get `WETHAIR_ERROR_UNSUPPORTED`), as a host lowers
/// detail with distance: the output blends from the old guides to the new over
/// `guides.blend_time`, and guides that start to be simulated start where the output showed
/// them (on the GPU backend one blocking read of the guides).
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_guide_fraction(sim: *mut WetHairSim, fraction: f32) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        s.0.set_guide_fraction(fraction)?;
        Ok(())
    })
}

/// Sets where every strand's root is at the end of the next step (or `wethair_sim_advance`
/// frame), for a simulation made with `skinned_roots`: `count` (the groom's strand count,
/// followers included where guides are on) positions (x y z each, m, world: the strand's
/// first point) and rotations (x y z w each, a unit quaternion: the turn from the groom's rest
/// frame to the world). Pinned points after the first keep their rest offset from it, turned. The roots move there over the step's
/// substeps as the head does. All or nothing: on error no frame changes.
///
/// # Safety
/// `sim` is valid; `positions` holds `count * 3` floats and `rotations` `count * 4`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_root_frames(
    sim: *mut WetHairSim,
    positions: *const f32,
    rotations: *const f32,
    count: u32,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        if positions.is_null() {
            return Err(super::boundary::null("positions"));
        }
        if rotations.is_null() {
            return Err(super::boundary::null("rotations"));
        }
        // The strand count (the host's groom's, followers included) is checked before the
        // arrays are read.
        let strands = s.0.stats_counts().0 as usize;
        if count as usize != strands {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                format!("count {count}: the groom has {strands} strands, give one frame each"),
            ));
        }
        let n = count as usize;
        let pos = std::slice::from_raw_parts(positions, n * 3);
        let rot = std::slice::from_raw_parts(rotations, n * 4);
        s.0.set_roots_by(n, |i| RootFrame {
            position: Vec3::from_slice(&pos[3 * i..]),
            rotation: glam::Quat::from_slice(&rot[4 * i..]),
        })?;
        Ok(())
    })
}

/// Adds `count` water particles at `positions` (x y z each, m, world space) with
/// `velocities` (x y z each, m/s; NULL = at rest). All or nothing: on error none is added.
///
/// # Safety
/// `sim` is valid; the arrays hold `count * 3` floats.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_add_water(
    sim: *mut WetHairSim,
    positions: *const f32,
    velocities: *const f32,
    count: u32,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        if count == 0 {
            return Ok(());
        }
        if positions.is_null() {
            return Err(super::boundary::null("positions"));
        }
        if count > MAX_WATER_CAPACITY {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_CAPACITY,
                format!("count {count} exceeds {MAX_WATER_CAPACITY}"),
            ));
        }
        let n = count as usize;
        let to_vec3 = |p: *const f32| -> Vec<Vec3> {
            std::slice::from_raw_parts(p, n * 3)
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect()
        };
        let pos = to_vec3(positions);
        let vel = if velocities.is_null() {
            Vec::new()
        } else {
            to_vec3(velocities)
        };
        s.0.add_water(&pos, &vel)?;
        Ok(())
    })
}

/// Removes every water particle; hair keeps its wetness.
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_clear_water(sim: *mut WetHairSim) -> WetHairResult {
    boundary!({
        nonnull_mut!(sim, "sim").0.clear_water()?;
        Ok(())
    })
}

/// Advances by `dt` seconds (0 < dt <= 1) in the desc's substeps. A step that produces a
/// non-finite value returns `WETHAIR_ERROR_UNSTABLE` (the message names the strand) and the
/// simulation keeps returning it, with no vertex output, until `wethair_sim_reset`.
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_step(sim: *mut WetHairSim, dt: f32) -> WetHairResult {
    boundary!({
        nonnull_mut!(sim, "sim").0.step(dt)?;
        Ok(())
    })
}

/// Advances by a host frame of `frame_time` seconds (finite, >= 0) in the desc's fixed steps
/// (`WetHairSimDesc::fixed_step`): the time is added to what the simulation owes, every whole
/// step in it is taken, and the rest waits for the next frame, so hosts at 30, 60 or 144 Hz
/// compute the same steps bit for bit. The head moves from where the last step left it to
/// the transform last set, reached at the end of this frame. With `interpolate`, the vertices
/// show the state between the last two steps by the time left over. Without a fixed step
/// this is `wethair_sim_step(sim, frame_time)`. `out` (may be NULL; the host sets its
/// `struct_size`) receives what the call did, only on success.
///
/// # Safety
/// `sim` is valid; `out` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_advance(
    sim: *mut WetHairSim,
    frame_time: f32,
    out: *mut WetHairAdvance,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let out = if out.is_null() {
            None
        } else {
            Some(check_out_size!(out, WetHairAdvance, "out"))
        };
        let a = s.0.advance(frame_time)?;
        if let Some(out) = out {
            out.write(WetHairAdvance {
                struct_size: std::mem::size_of::<WetHairAdvance>() as u32,
                steps: a.steps,
                blend: a.blend,
                dropped_time: a.dropped,
            });
        }
        Ok(())
    })
}

/// Returns to the rest pose at the current head transform: still, dry, no water; an
/// instability is forgotten. After a device failure it returns `WETHAIR_ERROR_DEVICE` and
/// changes nothing (destroy the simulation).
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_reset(sim: *mut WetHairSim) -> WetHairResult {
    boundary!({
        nonnull_mut!(sim, "sim").0.reset()?;
        Ok(())
    })
}

/// Describes the vertex buffer: count, stride and byte offsets of the requested attributes.
/// The host sets `out->struct_size = sizeof(WetHairVertexLayout)` first.
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_vertex_layout(
    sim: *const WetHairSim,
    out: *mut WetHairVertexLayout,
) -> WetHairResult {
    boundary!({
        let s = nonnull!(sim, "sim");
        let out = check_out_size!(out, WetHairVertexLayout, "out");
        s.0.device_ok()?;
        let a = s.0.attributes();
        let off = |bit| a.offset(bit).map_or(-1, |o| (o * 4) as i32);
        out.write(WetHairVertexLayout {
            struct_size: std::mem::size_of::<WetHairVertexLayout>() as u32,
            vertex_count: s.0.vertex_count() as u32,
            strand_count: s.0.stats_counts().0,
            stride_floats: a.stride() as u32,
            position_offset: off(VertexAttributes::POSITION),
            tangent_offset: off(VertexAttributes::TANGENT),
            wetness_offset: off(VertexAttributes::WETNESS),
        });
        Ok(())
    })
}

/// Copies the requested attributes of every vertex into `dst` (`capacity` floats; it needs
/// `vertex_count * stride_floats`) and stores the floats written in `written`. On any error
/// nothing is written, `written` included. On the GPU backend this is the readback: with
/// `WETHAIR_READBACK_LATEST` it waits for the last step; with
/// `WETHAIR_READBACK_PREVIOUS_FRAME` it returns the step before without waiting.
///
/// # Safety
/// `sim` is valid; `dst` holds `capacity` floats; `written` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_vertex_buffer(
    sim: *mut WetHairSim,
    dst: *mut f32,
    capacity: usize,
    written: *mut usize,
) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        if dst.is_null() || written.is_null() {
            return Err(super::boundary::null("dst or written"));
        }
        let need = s.0.vertex_count() * s.0.attributes().stride();
        if capacity < need {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_BUFFER_TOO_SMALL,
                format!("capacity {capacity} floats, {need} needed"),
            ));
        }
        if let Some(e) = s.0.failed() {
            return Err(e.clone().into());
        }
        let n = s.0.write_vertices(std::slice::from_raw_parts_mut(dst, need))?;
        written.write(n);
        Ok(())
    })
}

/// Copies every water particle's position (x y z each, m) into `dst` and stores the count
/// in `written`. `capacity` is in particles (`dst` holds `capacity * 3` floats); a buffer
/// smaller than the particles held is refused with `WETHAIR_ERROR_BUFFER_TOO_SMALL`, as a
/// short vertex buffer is, and nothing is written (the count is `WetHairStats::particles`,
/// and at most `WetHairWaterDesc::capacity`). On the GPU backend the particles come sorted by
/// their bits, the same order every run; a shared water buffer holds them in the device's
/// order, which may differ from run to run.
///
/// # Safety
/// `sim` is valid; `dst` holds `capacity * 3` floats (may be NULL when `capacity` is 0);
/// `written` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_water(
    sim: *const WetHairSim,
    dst: *mut f32,
    capacity: u32,
    written: *mut u32,
) -> WetHairResult {
    boundary!({
        let s = nonnull!(sim, "sim");
        if written.is_null() || (dst.is_null() && capacity > 0) {
            return Err(super::boundary::null("dst or written"));
        }
        s.0.device_ok()?;
        let w = s.0.water_positions()?;
        if w.len() > capacity as usize {
            return Err(Fail(
                WetHairResult::WETHAIR_ERROR_BUFFER_TOO_SMALL,
                format!("capacity {capacity} particles, {} held", w.len()),
            ));
        }
        if !w.is_empty() {
            std::slice::from_raw_parts_mut(dst, w.len() * 3).copy_from_slice(bytemuck::cast_slice(&w));
        }
        written.write(w.len() as u32);
        Ok(())
    })
}

/// Fills `out` with counters and measures. The host sets `out->struct_size` first. The
/// measures are taken now: the clumping measures search the strands (6.5 ms on a 10,000-strand
/// groom, 75 ms on 100,000, on 2 CPU threads), and on the GPU backend the state is read back.
/// For every frame, call `wethair_sim_get_counters`.
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_stats(sim: *const WetHairSim, out: *mut WetHairStats) -> WetHairResult {
    boundary!({ write_stats(sim, out, Simulation::stats) })
}

/// Since 0.6.0: fills `out` with the counters of `wethair_sim_get_stats` (counts, timing, the
/// integrator and substeps, the water ledger) without its measures: `clumping`,
/// `clumping_along`, `error_estimate` and `error_estimate_max` are -1. No search and no read of
/// the positions: on the CPU backend a few loads (and the ledger's sums, with held water), for
/// every frame; on the GPU backend it waits for the last step (a 32-byte status read, and with
/// held water each point's water and the particles for the ledger). The host sets
/// `out->struct_size` first.
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_counters(sim: *const WetHairSim, out: *mut WetHairStats) -> WetHairResult {
    boundary!({ write_stats(sim, out, Simulation::counters) })
}

/// The body of both stats entry points: checks `sim` and `out`, then writes `take(sim)` with
/// the water ledger (nothing written on failure).
///
/// # Safety
/// As the entry points': `sim` is valid; `out` is writable.
unsafe fn write_stats(
    sim: *const WetHairSim,
    out: *mut WetHairStats,
    take: fn(&Simulation) -> crate::sim::Stats,
) -> Result<(), Fail> {
    let s = nonnull!(sim, "sim");
    let out = check_out_size!(out, WetHairStats, "out");
    s.0.device_ok()?;
    let ledger = s.0.try_water_ledger()?.unwrap_or_default();
    out.write(stats_out(&take(&s.0), &ledger));
    Ok(())
}

/// The C record of `st` and the water ledger.
fn stats_out(st: &crate::sim::Stats, ledger: &crate::engine::WaterLedger) -> WetHairStats {
    WetHairStats {
        struct_size: std::mem::size_of::<WetHairStats>() as u32,
        strands: st.strands,
        points: st.points,
        particles: st.particles,
        particles_removed: st.particles_removed,
        steps: st.steps,
        last_step_ms: st.last_step_ms,
        max_speed: st.max_speed,
        clumping: st.clumping,
        threads: st.threads,
        integrator: st.integrator as u32,
        backend: st.backend as u32,
        clumping_along: st.clumping_along,
        water_added: ledger.added,
        water_in_particles: ledger.in_particles,
        water_held: ledger.held,
        water_left: ledger.left,
        water_evaporated: ledger.evaporated,
        error_estimate: st.error_estimate.map_or(-1.0, |e| e.rms),
        error_estimate_max: st.error_estimate.map_or(-1.0, |e| e.max),
        substeps: st.substeps,
        reserved: 0,
    }
}

/// Says which backend runs `sim`, on which device, and why AUTO fell back to the CPU. The host
/// sets `out->struct_size` first.
///
/// # Safety
/// `sim` is valid; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_get_backend_info(
    sim: *const WetHairSim,
    out: *mut WetHairBackendInfo,
) -> WetHairResult {
    boundary!({
        let s = nonnull!(sim, "sim");
        let out = check_out_size!(out, WetHairBackendInfo, "out");
        s.0.device_ok()?;
        let info = s.0.backend_info();
        let mut rec = WetHairBackendInfo {
            struct_size: std::mem::size_of::<WetHairBackendInfo>() as u32,
            backend: info.backend as u32,
            device: [0; 128],
            fallback_reason: [0; 256],
        };
        copy_c_string(&info.device, &mut rec.device);
        copy_c_string(&info.fallback_reason, &mut rec.fallback_reason);
        out.write(rec);
        Ok(())
    })
}

/// Copies `s` into `dst` as a NUL-terminated string, cut at a character boundary to fit.
fn copy_c_string(s: &str, dst: &mut [std::ffi::c_char]) {
    let mut end = s.len().min(dst.len() - 1);
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    for (d, &b) in dst.iter_mut().zip(&s.as_bytes()[..end]) {
        *d = b as std::ffi::c_char;
    }
    dst[end] = 0;
}

/// Makes a GPU simulation's device fail as a lost device would, so that a host can test its
/// error path: every later call on `sim` (reset and the reads included; destroy excepted)
/// returns `WETHAIR_ERROR_DEVICE`, as after a real loss. No effect on the CPU backend. For
/// tests only.
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_debug_lose_device(sim: *mut WetHairSim) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        s.0.debug_lose_device();
        Ok(())
    })
}
