//! Hair-hair volume (issue 17, item 4; `physics/volume.rs`, docs/VOLUME.md): under gravity the
//! paper groom keeps most of its filled silhouette where it collapses onto the head without;
//! wet hair still clumps with it on; the GPU keeps it as the CPU does; results are the same on
//! any thread count and GPU run after run; a scene without it has no pass; bad parameters are
//! refused by name, through Rust and C.

use crate::common::{backends, max_diff, serial};
use glam::Vec3;
use wethair::groom::paper_scene;
use wethair::plan::Pass;
use wethair::scenes::{on_hair, Lcg};
use wethair::{Backend, Error, Integrator, SimParams, Simulation, Volume};

/// The volume of the 1 cm voxels holding a point, m³: the groom's silhouette, filled.
fn occupied(x: &[Vec3]) -> f32 {
    let mut v: Vec<[i32; 3]> = x.iter().map(|p| (*p / 0.01).floor().as_ivec3().to_array()).collect();
    v.sort_unstable();
    v.dedup();
    v.len() as f32 * 1e-6
}

/// The paper groom (3,000 strands of 12 points on a 0.1 m head, AUTO's integrator) with
/// `volume`, on the CPU.
fn paper(volume: Volume, threads: u32) -> Simulation {
    paper_on(Backend::CPU, volume, threads)
}

/// The same on `backend`.
fn paper_on(backend: Backend, volume: Volume, threads: u32) -> Simulation {
    let g = paper_scene(3000, 12).unwrap();
    let p = SimParams {
        backend,
        threads,
        integrator: Integrator::AUTO,
        volume,
        ..SimParams::paper_scene_with_head()
    };
    Simulation::new(&g, p).unwrap()
}

/// The smallest filled silhouette over frames 30 to 90 (after the first fall), over the rest's.
fn least_silhouette(s: &mut Simulation) -> f32 {
    let rest = occupied(&s.positions());
    let mut least = f32::INFINITY;
    for f in 0..90 {
        s.step(1.0 / 60.0).unwrap();
        if f >= 29 {
            least = least.min(occupied(&s.positions()) / rest);
        }
    }
    least
}

#[test]
fn a_groom_keeps_its_volume_under_gravity_where_it_collapses_without() {
    let _serial = serial();
    let without = least_silhouette(&mut paper(Volume::OFF, 0));
    let with = least_silhouette(&mut paper(Volume::ON, 0));
    eprintln!("filled silhouette under gravity: {without:.3} of rest without volume, {with:.3} with");
    // Measured (2026-11-25): 0.17 without, 0.63 with the defaults (pressure 1; the first
    // default, 10, kept 0.78 by boiling: see a_groom_with_volume_settles).
    assert!(
        without < 0.4,
        "without volume the groom kept {without} of its silhouette"
    );
    assert!(with > 0.55, "with volume the groom kept only {with} of its silhouette");
}

/// With volume on the groom settles as it does without: after 150 frames under gravity its
/// mean point speed is within twice the speed without volume, and no point moves faster than
/// 5 m/s (the first default pressure, past the step's stability limit, left the groom boiling
/// at 3 m/s on average with tips at 25 m/s).
#[test]
fn a_groom_with_volume_settles() {
    let _serial = serial();
    let settle = |volume: Volume| {
        let mut s = paper(volume, 0);
        for _ in 0..150 {
            s.step(1.0 / 60.0).unwrap();
        }
        let v = s.velocities();
        let mean = v.iter().map(|x| x.length()).sum::<f32>() / v.len() as f32;
        (mean, v.iter().map(|x| x.length()).fold(0.0f32, f32::max))
    };
    let (off, off_max) = settle(Volume::OFF);
    let (on, on_max) = settle(Volume::ON);
    eprintln!("after 150 frames: mean speed {off:.3} m/s without volume, {on:.3} with; fastest {off_max:.2} and {on_max:.2} m/s");
    assert!(
        on < 2.0 * off,
        "the groom boils with volume on: mean speed {on} m/s against {off}"
    );
    assert!(on_max < 5.0, "a point moves at {on_max} m/s with volume on");
}

/// The paper's wet scene with volume on clumps as much as issue 14 asks of wet hair (at most
/// 0.7 of the dry spacing), on both backends: wet hair leaves the volume as it soaks (its dry
/// share of mass is spread), so the dry hair's pressure does not spread the bundles again.
#[test]
fn wet_hair_still_clumps_with_volume_on() {
    let _serial = serial();
    // The paper's wet scene (10,000 strands of 6 points, 1,000 drops in the hair), for its
    // first half second (a minute of lavapipe for the first second, a quarter of that here).
    let g = paper_scene(10_000, 6).unwrap();
    let sim = |backend: Backend, volume: Volume| {
        let p = SimParams {
            backend,
            volume,
            ..SimParams::paper_scene_with_head()
        };
        Simulation::new(&g, p).unwrap()
    };
    let water = on_hair(&sim(Backend::CPU, Volume::OFF).positions(), 1000, &mut Lcg(3));
    let clumping = |mut runs: [Simulation; 2]| {
        runs[1].add_water(&water, &[]).unwrap();
        for _ in 0..30 {
            for s in runs.iter_mut() {
                s.step(1.0 / 60.0).unwrap();
            }
        }
        runs.each_ref().map(|s| s.stats().clumping)
    };
    let off = clumping([sim(Backend::CPU, Volume::OFF), sim(Backend::CPU, Volume::OFF)]);
    for backend in backends() {
        let on = clumping([sim(backend, Volume::ON), sim(backend, Volume::ON)]);
        eprintln!(
            "{backend:?}: clumping with volume on: dry {:.5} m, wet {:.5} m ({:.2}); off (CPU): dry {:.5} m, wet {:.5} m ({:.2})",
            on[0],
            on[1],
            on[1] / on[0],
            off[0],
            off[1],
            off[1] / off[0]
        );
        // Measured (2026-11-26, after 100 frames): with volume 1.52 mm wet against 3.51 mm dry
        // (0.43); without, 2.02 against 3.24 mm (0.62). When the pressure was only scaled by
        // 1 - wetness and wet hair still filled the grid: 3.26 against 3.51 mm (0.93). After
        // the 60 frames run here (2026-12-02): 1.28 mm against 4.57 (0.28) on the CPU, 1.26
        // against 4.55 on lavapipe; without volume 1.63 against 3.18 (0.51). After the 30
        // frames run now (2026-12-03): 2.14 mm against 5.39 (0.40) on the CPU, 2.14 against
        // 5.38 on lavapipe; without volume 1.95 against 3.00 (0.65).
        assert!(
            on[1] < 0.7 * on[0],
            "{backend:?}: wet clumping {} against dry {}: the volume undid the bundles",
            on[1],
            on[0]
        );
    }
}

#[test]
fn volume_gives_the_same_bits_on_any_thread_count() {
    let _serial = serial();
    let bits = |threads: u32| -> Vec<[u32; 3]> {
        let mut s = paper(Volume::ON, threads);
        for _ in 0..20 {
            s.step(1.0 / 60.0).unwrap();
        }
        s.positions().iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    };
    assert!(bits(1) == bits(2), "1 and 2 threads differ");
}

#[test]
fn only_a_scene_with_volume_runs_the_pass() {
    let on = paper(Volume::ON, 1);
    assert_eq!(on.passes()[0], Pass::Volume);
    assert!(!paper(Volume::OFF, 1).passes().contains(&Pass::Volume));
}

/// The GPU's spread sums a workgroup's corners in a 256-slot table and sends a corner past a
/// full table straight to the grid. Cells of 5 mm, finer than the points' 9 mm spacing, give a
/// workgroup of 64 points (about 59 free, 8 corners each, few shared) more than 256 distinct
/// corners, so both ways run; the sums are integers, so the GPU equals the CPU as closely as
/// with coarse cells (lavapipe: 2.8e-7 m after 2 frames; coarse, 6.0e-7 m after 3).
#[test]
fn a_fine_volume_grid_spreads_on_the_gpu_as_on_the_cpu() {
    let _serial = serial();
    if !backends().contains(&Backend::GPU) {
        return;
    }
    let g0 = paper_scene(500, 12).unwrap();
    let run = |backend: Backend| {
        let p = SimParams {
            backend,
            // The pressure's stability limit at 5 mm cells and 60 Hz is (cell / dt)^2 = 0.09.
            volume: Volume {
                cell: 0.005,
                pressure: 0.05,
                ..Volume::ON
            },
            ..SimParams::paper_scene_with_head()
        };
        let mut s = Simulation::new(&g0, p).unwrap();
        for _ in 0..2 {
            s.step(1.0 / 60.0).unwrap();
        }
        s.positions()
    };
    let (c, g) = (run(Backend::CPU), run(Backend::GPU));
    let d = max_diff(&c, &g);
    eprintln!("fine volume grid: GPU {d:e} m from the CPU after 2 frames");
    assert!(d < 1e-5, "GPU {d} m from the CPU");
}

#[test]
fn the_gpu_keeps_the_volume_as_the_cpu_does() {
    let _serial = serial();
    if !backends().contains(&Backend::GPU) {
        return;
    }
    // GPU against CPU: the same spread and response (volume.wgsl mirrors physics/volume.rs).
    // The pressure makes the groom chaotic (a strand standing on the head falls one way or
    // the other): the CPU with gravity nudged by 1e-6 parts from itself as far as the GPU
    // does, so the GPU is held to that floor, and to 0.1 mm over the first 3 frames.
    let g0 = paper_scene(3000, 12).unwrap();
    let make = |backend: Backend, nudge: f32| {
        let p = SimParams {
            backend,
            integrator: Integrator::AUTO,
            volume: Volume::ON,
            gravity: Vec3::new(0.0, 0.0, -9.81 * (1.0 + nudge)),
            ..SimParams::paper_scene_with_head()
        };
        Simulation::new(&g0, p).unwrap()
    };
    let (mut c, mut n, mut g) = (
        make(Backend::CPU, 0.0),
        make(Backend::CPU, 1e-6),
        make(Backend::GPU, 0.0),
    );
    assert!(g.backend_info().backend == Backend::GPU);
    let gap = |a: &Simulation, b: &Simulation| max_diff(&a.positions(), &b.positions());
    for f in 0..10 {
        for s in [&mut c, &mut n, &mut g] {
            s.step(1.0 / 60.0).unwrap();
        }
        if f == 2 {
            let d = gap(&c, &g);
            eprintln!(
                "volume parity after 3 frames: GPU {d:e} m from the CPU, nudged CPU {:e}",
                gap(&c, &n)
            );
            assert!(d < 1e-4, "GPU {d} m from the CPU after 3 frames");
        }
    }
    let (d, floor) = (gap(&c, &g), gap(&c, &n));
    eprintln!("volume parity after 10 frames: GPU {d:e} m, nudged CPU {floor:e} m");
    assert!(
        d <= 2.0 * floor + 1e-3,
        "GPU {d} m from the CPU; CPU nudged 1e-6: {floor} m"
    );
    let kept = least_silhouette(&mut paper_on(Backend::GPU, Volume::ON, 0));
    eprintln!("GPU: filled silhouette {kept:.3} of rest");
    assert!(kept > 0.55, "the GPU kept only {kept} of the silhouette");
    // Integer sums: the same bits run after run.
    let bits = || -> Vec<[u32; 3]> {
        let mut s = paper_on(Backend::GPU, Volume::ON, 0);
        for _ in 0..10 {
            s.step(1.0 / 60.0).unwrap();
        }
        s.positions().iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    };
    assert!(bits() == bits(), "GPU runs differ");
}

#[test]
fn bad_volume_parameters_are_refused_by_name() {
    let g = paper_scene(100, 6).unwrap();
    for (v, want) in [
        (
            Volume {
                cell: 0.0,
                ..Volume::ON
            },
            "volume.cell",
        ),
        (
            Volume {
                cell: f32::NAN,
                ..Volume::ON
            },
            "volume.cell",
        ),
        (
            Volume {
                pressure: -1.0,
                ..Volume::ON
            },
            "volume.pressure",
        ),
        (
            Volume {
                friction: f32::INFINITY,
                ..Volume::ON
            },
            "volume.friction",
        ),
        (
            Volume {
                rest_density: -2.0,
                ..Volume::ON
            },
            "volume.rest_density",
        ),
        (
            Volume {
                cell: 1e-4,
                ..Volume::ON
            },
            "volume grid",
        ),
    ] {
        let p = SimParams {
            backend: Backend::CPU,
            volume: v,
            ..SimParams::paper()
        };
        match Simulation::new(&g, p) {
            Err(Error::InvalidArgument(m) | Error::Capacity(m)) => assert!(m.contains(want), "{m}"),
            other => panic!("{want}: {other:?}"),
        }
    }
}

mod c_abi {
    //! Hair-hair volume through the C ABI: `WetHairSimDesc::volume`.

    use std::ptr::null_mut;
    use wethair::ffi::*;
    use WetHairResult::*;

    use crate::common::last_error;

    #[test]
    fn volume_reaches_c_hosts() {
        let mut g = null_mut();
        assert_eq!(unsafe { wethair_groom_create_paper_scene(50, 6, &mut g) }, WETHAIR_OK);
        let make = |edit: &dyn Fn(&mut WetHairVolume)| {
            let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
            let size = std::mem::size_of::<WetHairSimDesc>() as u32;
            assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
            let mut d = unsafe { d.assume_init() };
            assert_eq!(d.volume.enabled, 0, "off by default");
            assert_eq!(d.volume.cell, 0.02, "the documented cell");
            d.groom = g;
            d.backend = wethair::Backend::CPU as u32;
            d.volume.enabled = 1;
            edit(&mut d.volume);
            let mut s = null_mut();
            let r = unsafe { wethair_sim_create(&d, &mut s) };
            (r, s)
        };
        let (r, s) = make(&|_| {});
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        unsafe { wethair_sim_destroy(s) };
        type Edit = fn(&mut WetHairVolume);
        let cases: [(Edit, WetHairResult, &str); 3] = [
            (|v| v.enabled = 2, WETHAIR_ERROR_INVALID_ARGUMENT, "volume.enabled"),
            (
                |v| v.pressure = f32::NAN,
                WETHAIR_ERROR_INVALID_ARGUMENT,
                "volume.pressure",
            ),
            (|v| v.cell = 1e-4, WETHAIR_ERROR_CAPACITY, "volume grid"),
        ];
        for (edit, code, name) in cases {
            let (r, s) = make(&|v| edit(v));
            assert_eq!((r, s.is_null()), (code, true), "{name}: {}", last_error());
            assert!(last_error().contains(name), "{}", last_error());
        }
        unsafe { wethair_groom_destroy(g) };
    }
}
