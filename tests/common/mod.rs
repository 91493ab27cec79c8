//! Helpers shared by the test files that run both backends (`tests/all.rs` declares it once).

use wethair::groom::paper_scene;
use wethair::{Backend, SimParams, Simulation};

/// Tests that take this lock run one at a time: each starts worker pools and (software) GPU devices
/// whose threads, run side by side on a 2-core machine, starve one another.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Holds the lock for the test's duration.
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// The backends to test: the CPU, and the GPU when it starts (it must under
/// `WETHAIR_REQUIRE_GPU=1`).
pub fn backends() -> Vec<Backend> {
    let probe = Simulation::new(
        &paper_scene(8, 3).unwrap(),
        SimParams {
            backend: Backend::GPU,
            ..SimParams::paper()
        },
    );
    match probe {
        Ok(_) => vec![Backend::CPU, Backend::GPU],
        Err(e) if std::env::var("WETHAIR_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("WETHAIR_REQUIRE_GPU=1 but the GPU backend failed: {e}")
        }
        Err(e) => {
            eprintln!("no GPU adapter, these cases run on the CPU only: {e}");
            vec![Backend::CPU]
        }
    }
}

/// The library's last error message on this thread (the C ABI's `wethair_last_error_message`).
pub fn last_error() -> String {
    unsafe { std::ffi::CStr::from_ptr(wethair::ffi::wethair_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// Every strand's root frame as a head at `head` (rotation and translation) would hold it:
/// its rest root moved by the head, turned by the head's rotation. Skinned roots given these
/// frames move hair as the head transform does.
pub fn frames_on_head(g: &wethair::groom::Groom, head: glam::Mat4) -> Vec<wethair::physics::roots::RootFrame> {
    let (_, rotation, _) = head.to_scale_rotation_translation();
    (0..g.strand_count())
        .map(|s| wethair::physics::roots::RootFrame {
            position: head.transform_point3(g.positions()[g.strand_range(s).start]),
            rotation,
        })
        .collect()
}

/// `frames` carried rigidly: turned by `turn` about the origin, then moved by `away`.
pub fn frames_moved(
    frames: &[wethair::physics::roots::RootFrame],
    turn: glam::Quat,
    away: glam::Vec3,
) -> Vec<wethair::physics::roots::RootFrame> {
    frames
        .iter()
        .map(|f| wethair::physics::roots::RootFrame {
            position: turn * f.position + away,
            rotation: turn * f.rotation,
        })
        .collect()
}
