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

/// `g` with every free point moved sideways (x and y) by up to 1e-7 m, drawn from `seed`.
/// A real GPU rounds differently from the CPU (fused multiply-adds: its hair is 3e-8 m off
/// the CPU's after one frame on an H100), sideways too, which is what decides the way a strand
/// buckles on a surface or parts at a bundle. The CPU against itself on this groom is the
/// chaos floor a GPU-against-CPU comparison is held to; a nudge of the water or the head alone
/// can miss that sideways channel.
pub fn nudged_groom(g: &wethair::groom::Groom, seed: u32) -> wethair::groom::Groom {
    let mut rng = wethair::scenes::Lcg(seed);
    let pinned = g.pinned();
    let pos = g
        .positions()
        .iter()
        .zip(pinned)
        .map(|(p, &pin)| {
            let (dx, dy) = (rng.next_f32() - 0.5, rng.next_f32() - 0.5);
            if pin {
                *p
            } else {
                *p + 2e-7 * glam::Vec3::new(dx, dy, 0.0)
            }
        })
        .collect();
    let counts: Vec<u32> = (0..g.strand_count()).map(|s| g.strand_range(s).len() as u32).collect();
    wethair::groom::Groom::new(pos, &counts, Some(pinned.to_vec()), Some(g.masses().to_vec()), 0.0).unwrap()
}

/// The largest distance between matching points of `a` and `b`, m.
pub fn max_diff(a: &[glam::Vec3], b: &[glam::Vec3]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f32::max)
}

/// How many places the points at `p` occupy, bit for bit (coalesced drops share one).
pub fn places(p: &[glam::Vec3]) -> usize {
    let mut bits: Vec<[u32; 3]> = p.iter().map(|v| v.to_array().map(f32::to_bits)).collect();
    bits.sort_unstable();
    bits.dedup();
    bits.len()
}

/// Runs test `name` (its full path, e.g. `gpu::some_test`) again, alone, in a child process of
/// this test binary with `marker` set in its environment, and asserts that it ran and passed.
/// Returns false in that child (where the test goes on to its check), true in the parent (where
/// the test is done). For checks that count what the whole process holds (heap bytes,
/// descriptors, threads), which the other tests of this binary would disturb.
pub fn ran_alone(name: &str, marker: &str) -> bool {
    if std::env::var_os(marker).is_some() {
        return false;
    }
    let out = std::process::Command::new(std::env::current_exe().expect("test binary"))
        .args([name, "--exact", "--test-threads=1", "--nocapture"])
        .env(marker, "1")
        .output()
        .expect("the test binary runs again");
    let text = String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "the check alone failed:\n{text}");
    // It must have run the check, not filtered it out.
    assert!(text.contains("1 passed"), "the check did not run alone:\n{text}");
    true
}
