//! Defects found by hostile input and real groom files (issue 13), each pinned by the exact
//! outcome it must now have: the strand an instability names, every call after a lost device,
//! and bit-identical results for any thread count with water.

use glam::{Mat4, Vec3};
use std::ffi::CStr;
use std::ptr::null_mut;
use wethair::ffi::*;
use wethair::groom::paper_scene;
use wethair::physics::collide::Shape;
use wethair::scenes::{shower, Lcg};
use wethair::{Backend, Error, Integrator, SimParams, Simulation};
use WetHairResult::*;

/// One test at a time: each starts worker pools and (software) GPU devices.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// The CPU, and the GPU when it starts (it must under `WETHAIR_REQUIRE_GPU=1`).
fn backends() -> Vec<Backend> {
    let probe = Simulation::new(
        &paper_scene(8, 3).unwrap(),
        SimParams {
            backend: Backend::GPU,
            ..Default::default()
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

fn last_error() -> String {
    unsafe { CStr::from_ptr(wethair_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// Item 2: one substep per frame blows the paper scene up, and the error names a strand of
/// the groom (it named 4294967295 when a finite speed's square overflowed).
#[test]
fn an_instability_names_a_strand_of_the_groom() {
    let _s = serial();
    let groom = paper_scene(16, 6).unwrap();
    for backend in backends() {
        let params = SimParams {
            substeps: 1,
            backend,
            ..Default::default()
        };
        let mut sim = Simulation::new(&groom, params).unwrap();
        let mut v = vec![0.0f32; sim.vertex_count() * sim.attributes().stride()];
        let err = (0..600)
            .find_map(|_| sim.step(1.0 / 60.0).and_then(|_| sim.write_vertices(&mut v)).err())
            .unwrap_or_else(|| panic!("{backend:?}: 1 substep at 1/60 s should diverge"));
        match &err {
            Error::Unstable { strand: Some(s), .. } => assert!(*s < 16, "{backend:?}: {err}"),
            e => panic!("{backend:?}: expected an instability naming a strand, got {e}"),
        }
        let msg = err.to_string();
        assert!(
            msg.starts_with("unstable: strand ") && !msg.contains("4294967295"),
            "{msg}"
        );
    }
}

/// Item 3: after the device is lost on a simulation holding water, every call returns
/// `WETHAIR_ERROR_DEVICE` (the header's promise), and nothing is written.
#[test]
fn every_call_after_a_lost_device_returns_device() {
    let _s = serial();
    if !backends().contains(&Backend::GPU) {
        return; // no adapter and not required: the CPU has no device to lose
    }
    unsafe {
        let mut g = null_mut();
        assert_eq!(wethair_groom_create_paper_scene(32, 6, &mut g), WETHAIR_OK);
        let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
        wethair_sim_desc_default(d.as_mut_ptr());
        let mut d = d.assume_init();
        d.groom = g;
        d.backend = Backend::GPU as u32;
        let mut s = null_mut();
        assert_eq!(wethair_sim_create(&d, &mut s), WETHAIR_OK, "{}", last_error());
        let (pos, vel) = shower(100, &mut Lcg(1));
        let (p, v): (Vec<f32>, Vec<f32>) = (bytemuck::cast_slice(&pos).to_vec(), bytemuck::cast_slice(&vel).to_vec());
        assert_eq!(wethair_sim_add_water(s, p.as_ptr(), v.as_ptr(), 100), WETHAIR_OK);
        assert_eq!(wethair_sim_step(s, 1.0 / 60.0), WETHAIR_OK);
        assert_eq!(wethair_sim_debug_lose_device(s), WETHAIR_OK);

        let m = Mat4::IDENTITY.to_cols_array();
        let mut stats = std::mem::zeroed::<WetHairStats>();
        stats.struct_size = std::mem::size_of::<WetHairStats>() as u32;
        stats.steps = 777;
        let mut layout = std::mem::zeroed::<WetHairVertexLayout>();
        layout.struct_size = std::mem::size_of::<WetHairVertexLayout>() as u32;
        let mut info = std::mem::zeroed::<WetHairBackendInfo>();
        info.struct_size = std::mem::size_of::<WetHairBackendInfo>() as u32;
        let mut buf = vec![-7.0f32; 32 * 6 * 7];
        let (mut written, mut wn) = (5usize, 5u32);
        let mut water = vec![-7.0f32; 300];
        let calls: [(&str, WetHairResult); 10] = [
            ("add_water", wethair_sim_add_water(s, p.as_ptr(), v.as_ptr(), 100)),
            ("set_head_transform", wethair_sim_set_head_transform(s, m.as_ptr())),
            ("clear_water", wethair_sim_clear_water(s)),
            ("reset", wethair_sim_reset(s)),
            ("get_stats", wethair_sim_get_stats(s, &mut stats)),
            ("step", wethair_sim_step(s, 1.0 / 60.0)),
            (
                "get_vertex_buffer",
                wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), buf.len(), &mut written),
            ),
            ("get_water", wethair_sim_get_water(s, water.as_mut_ptr(), 100, &mut wn)),
            ("get_vertex_layout", wethair_sim_get_vertex_layout(s, &mut layout)),
            ("get_backend_info", wethair_sim_get_backend_info(s, &mut info)),
        ];
        for (name, r) in calls {
            assert_eq!(r, WETHAIR_ERROR_DEVICE, "{name} after a lost device");
        }
        assert!(last_error().contains("GPU device error"), "{}", last_error());
        assert_eq!(stats.steps, 777, "stats written on failure");
        assert_eq!((written, wn), (5, 5), "counts written on failure");
        assert!(buf.iter().chain(&water).all(|&x| x == -7.0), "data written on failure");
        assert_eq!(layout.vertex_count, 0, "layout written on failure");
        // A second reset still refuses: the device does not come back.
        assert_eq!(wethair_sim_reset(s), WETHAIR_ERROR_DEVICE);
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

/// Vertex buffer after `frames` wet frames of a 96-strand groom under a shower, with the head
/// sphere and a capsule collider, on `threads` CPU threads.
fn wet_run(integrator: Integrator, threads: u32, frames: usize) -> Vec<u32> {
    let groom = paper_scene(96, 8).unwrap();
    let mut params = SimParams::paper_scene_with_head();
    params.colliders.push(Shape::Capsule {
        a: Vec3::new(-0.2, 0.0, -0.15),
        b: Vec3::new(0.2, 0.0, -0.15),
        radius: 0.03,
    });
    params.integrator = integrator;
    params.threads = threads;
    params.backend = Backend::CPU;
    let mut sim = Simulation::new(&groom, params).unwrap();
    let mut rng = Lcg(7);
    let mut v = vec![0.0f32; sim.vertex_count() * sim.attributes().stride()];
    for f in 0..frames {
        if f % 10 == 0 {
            let (pos, vel) = shower(300, &mut rng);
            sim.add_water(&pos, &vel).unwrap();
        }
        sim.step(1.0 / 60.0).unwrap();
    }
    sim.write_vertices(&mut v).unwrap();
    assert!(sim.stats().particles > 0, "water must stay in the scene");
    v.iter().map(|x| x.to_bits()).collect()
}

/// Item 6: with water and colliders, every integrator gives bit-identical vertices after 100
/// wet frames on 1, 2, 3 and 8 threads, and across runs.
#[test]
fn cpu_results_do_not_depend_on_the_thread_count_with_water() {
    let _s = serial();
    for integrator in [
        Integrator::SYMPLECTIC_EULER,
        Integrator::IMPLICIT_EULER,
        Integrator::XPBD,
    ] {
        let one = wet_run(integrator, 1, 100);
        assert_eq!(one, wet_run(integrator, 1, 100), "{integrator:?}: two runs differ");
        for threads in [2, 3, 8] {
            let other = wet_run(integrator, threads, 100);
            let differ = one.iter().zip(&other).filter(|(a, b)| a != b).count();
            assert_eq!(
                differ, 0,
                "{integrator:?}: {threads} threads differ from 1 in {differ} floats"
            );
        }
    }
}

/// Items 8 and 14 through C: `wethair_groom_load_with_desc` with units and axes; a bad enum or
/// float names its field; sizes outside first-release..=now are refused naming the range.
#[test]
fn load_desc_through_c_and_struct_size_ranges() {
    let path = std::ffi::CString::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ponytail_back.tfx")).unwrap();
    unsafe {
        let mut d = std::mem::MaybeUninit::<WetHairLoadDesc>::zeroed();
        wethair_load_desc_default(d.as_mut_ptr());
        let mut d = d.assume_init();
        assert_eq!(d.struct_size as usize, std::mem::size_of::<WetHairLoadDesc>());
        d.scale = 0.01;
        d.up_axis = wethair::groom::UpAxis::Y_TO_Z as u32;
        let mut g = null_mut();
        assert_eq!(
            wethair_groom_load_with_desc(path.as_ptr(), &d, &mut g),
            WETHAIR_OK,
            "{}",
            last_error()
        );
        let (mut ns, mut np) = (0, 0);
        assert_eq!(wethair_groom_get_counts(g, &mut ns, &mut np), WETHAIR_OK);
        assert_eq!((ns, np), (517, 517 * 16));
        wethair_groom_destroy(g);

        let sentinel = 0x5a5a as *mut WetHairGroom;
        for (field, patch) in [
            (
                "up_axis",
                (|d: &mut WetHairLoadDesc| d.up_axis = 7) as fn(&mut WetHairLoadDesc),
            ),
            ("scale", |d| d.scale = -1.0),
            ("linear_density", |d| d.linear_density = f32::NAN),
            ("strand_stride", |d| d.strand_stride = 0),
        ] {
            let mut bad = d;
            patch(&mut bad);
            let mut out = sentinel;
            let r = wethair_groom_load_with_desc(path.as_ptr(), &bad, &mut out);
            assert_eq!(r, WETHAIR_ERROR_INVALID_ARGUMENT, "{field}");
            assert!(last_error().contains(field), "{field}: {}", last_error());
            assert_eq!(out, sentinel, "{field}: output written on failure");
        }
        let mut big = d;
        big.struct_size += 4;
        let mut out = sentinel;
        assert_eq!(
            wethair_groom_load_with_desc(path.as_ptr(), &big, &mut out),
            WETHAIR_ERROR_STRUCT_SIZE
        );
        assert!(
            last_error().contains("accepts sizeof(WetHairLoadDesc) of 28"),
            "{}",
            last_error()
        );
    }
    for (name, first, now) in struct_sizes() {
        assert!(first <= now && first >= 8, "{name}: first {first}, now {now}");
    }
}
