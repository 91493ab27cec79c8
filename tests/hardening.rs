//! Defects found by hostile input and real groom files (issue 13), each pinned by the exact
//! outcome it must now have: the strand an instability names, every call after a lost device,
//! and bit-identical results for any thread count with water.

use glam::{Mat4, Vec3};
use std::ptr::null_mut;
use wethair::ffi::*;
use wethair::groom::paper_scene;
use wethair::physics::collide::Shape;
use wethair::scenes::{shower, Lcg};
use wethair::{Backend, Error, HeldWater, Integrator, SimParams, Simulation, WaterLedger};
use WetHairResult::*;

use crate::common::{backends, serial};

use crate::common::last_error;

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
            ..SimParams::paper()
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
        let calls: [(&str, WetHairResult); 11] = [
            ("add_water", wethair_sim_add_water(s, p.as_ptr(), v.as_ptr(), 100)),
            ("set_head_transform", wethair_sim_set_head_transform(s, m.as_ptr())),
            ("clear_water", wethair_sim_clear_water(s)),
            ("reset", wethair_sim_reset(s)),
            ("get_stats", wethair_sim_get_stats(s, &mut stats)),
            ("get_counters", wethair_sim_get_counters(s, &mut stats)),
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
        Integrator::BDF2,
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

/// A hundred thousand drops on the paper scene's hair (`held_water`: the wet model), stepped
/// two frames on `threads`: the hair's positions and the drops' (sorted) as bits, and the
/// water ledger where the model keeps one.
fn hundred_thousand_drops(threads: u32, held_water: HeldWater) -> (Vec<u32>, Vec<u32>, Option<WaterLedger>) {
    let groom = paper_scene(10_000, 6).unwrap();
    let mut params = SimParams::paper_scene_with_head();
    params.threads = threads;
    params.backend = Backend::CPU;
    params.held_water = held_water;
    params.water.capacity = 100_000;
    let mut sim = Simulation::new(&groom, params).unwrap();
    let drops = wethair::scenes::on_hair(groom.positions(), 100_000, &mut Lcg(3));
    sim.add_water(&drops, &[]).unwrap();
    for _ in 0..2 {
        sim.step(1.0 / 60.0).unwrap();
    }
    let mut w = sim.water_positions().unwrap();
    w.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
    let bits = |v: &[Vec3]| -> Vec<u32> { v.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect() };
    (bits(&sim.positions()), bits(&w), sim.water_ledger())
}

/// Many particles take the shared paths of the water's passes: the grid's moves into cell
/// order in chunks (over 16,384 particles) and the reactions summed by ranges of particles
/// (over 65,536 a substep). Positions and particles come out the same on 1, 2 and 3 threads.
#[test]
fn cpu_results_do_not_depend_on_the_thread_count_with_a_hundred_thousand_drops() {
    let _s = serial();
    let run = |threads: u32| {
        let (x, w, _) = hundred_thousand_drops(threads, HeldWater::OFF);
        (x, w)
    };
    let one = run(1);
    assert!(one.1.len() > 3 * 90_000, "the drops stay: {}", one.1.len() / 3);
    for threads in [2, 3] {
        assert!(run(threads) == one, "{threads} threads differ from 1");
    }
}

/// The same drops with the wet model ask for water from 1.6 million (point, drop) pairs in
/// the first substep: absorption shares its sums and grants among the pool's threads (over
/// 65,536 demands). Positions, drops and the ledger come out the same on 1, 2 and 3 threads.
#[test]
fn absorption_shared_among_threads_gives_the_same_bits() {
    let _s = serial();
    let run = |threads: u32| {
        let (x, w, ledger) = hundred_thousand_drops(threads, HeldWater::ON);
        (x, w, ledger.expect("the wet model keeps a ledger"))
    };
    let one = run(1);
    assert!(one.2.held > 0, "the hair drank: {:?}", one.2);
    for threads in [2, 3] {
        let other = run(threads);
        assert!(other.0 == one.0, "{threads} threads: positions differ from 1");
        assert!(other.1 == one.1, "{threads} threads: drops differ from 1");
        assert_eq!(other.2, one.2, "{threads} threads: ledger");
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
            last_error().contains("accepts sizeof(WetHairLoadDesc) of 32"),
            "{}",
            last_error()
        );
    }
    for (name, first, now) in struct_sizes() {
        assert!(first <= now && first >= 8, "{name}: first {first}, now {now}");
    }
}

/// The float values every field and argument is tried with: the extremes, tiny, denormal, 0.
const HOSTILE: [f32; 6] = [f32::MAX, -f32::MAX, 1e-30, 1e-40, 0.0, -1.0];

/// What a field is set to in one case of the sweep.
type Patch = Box<dyn Fn(&mut WetHairSimDesc, &mut Case)>;

/// A field's name and how to set it to a value.
type Field = (&'static str, Box<dyn Fn(f32) -> Patch>);

/// The parts of one sweep case outside the desc: water, head, dt, collider.
#[derive(Clone, Copy)]
struct Case {
    water_pos: [f32; 3],
    water_vel: [f32; 3],
    head: [f32; 16],
    dt: f32,
    collider: WetHairCollider,
}

/// Runs one case through C: create, add water, set the head, step 6 frames, read vertices and
/// water. Asserts that no call panics and that nothing non-finite is handed out with OK.
unsafe fn run_case(what: &str, mut d: WetHairSimDesc, mut c: Case, patch: &Patch) {
    patch(&mut d, &mut c);
    d.colliders = &c.collider;
    let mut s = null_mut();
    let r = wethair_sim_create(&d, &mut s);
    assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: create: {}", last_error());
    if r != WETHAIR_OK {
        assert!(s.is_null() && !last_error().is_empty(), "{what}");
        return;
    }
    let pos: Vec<f32> = (0..64)
        .flat_map(|i| [c.water_pos[0] + 0.005 * (i % 8) as f32, c.water_pos[1], c.water_pos[2]])
        .collect();
    let vel: Vec<f32> = (0..64).flat_map(|_| c.water_vel).collect();
    let calls = [
        wethair_sim_add_water(s, pos.as_ptr(), vel.as_ptr(), 64),
        wethair_sim_set_head_transform(s, c.head.as_ptr()),
    ];
    for r in calls {
        assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: {}", last_error());
    }
    let mut buf = vec![0.0f32; 16 * 6 * 7];
    let mut water = vec![0.0f32; 3 * 4096];
    for f in 0..6 {
        let r = wethair_sim_step(s, c.dt);
        assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: step {f}: {}", last_error());
        let mut n = 0usize;
        let r = wethair_sim_get_vertex_buffer(s, buf.as_mut_ptr(), buf.len(), &mut n);
        assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: vertices {f}: {}", last_error());
        if r == WETHAIR_OK {
            assert!(
                buf.iter().all(|x| x.is_finite()),
                "{what}: frame {f}: non-finite vertex with OK"
            );
        }
        let mut wn = 0u32;
        let r = wethair_sim_get_water(s, water.as_mut_ptr(), 4096, &mut wn);
        assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: water {f}: {}", last_error());
        if r == WETHAIR_OK {
            let w = &water[..3 * wn as usize];
            assert!(
                w.iter().all(|x| x.is_finite()),
                "{what}: frame {f}: non-finite particle with OK"
            );
        }
        let mut st = std::mem::zeroed::<WetHairStats>();
        st.struct_size = std::mem::size_of::<WetHairStats>() as u32;
        let r = wethair_sim_get_stats(s, &mut st);
        assert_ne!(r, WETHAIR_ERROR_PANIC, "{what}: stats: {}", last_error());
    }
    wethair_sim_destroy(s);
}

/// Item 1: every float field of the desc, the water's positions and velocities, the collider,
/// the head transform and dt, set to each hostile value (and the neighbours of their
/// documented limits), on both backends: no call returns `WETHAIR_ERROR_PANIC`, and nothing
/// non-finite is reported with `WETHAIR_OK`.
#[test]
fn hostile_floats_never_panic_nor_leak_non_finite_values() {
    let _s = serial();
    macro_rules! field {
        (@set $d:ident $c:ident $v:ident case . $($rest:tt)+) => { $c.$($rest)+ = $v };
        (@set $d:ident $c:ident $v:ident $($rest:tt)+) => { $d.$($rest)+ = $v };
        ($($path:tt)+) => {
            (
                stringify!($($path)+),
                Box::new(|v: f32| -> Patch {
                    Box::new(move |d: &mut WetHairSimDesc, c: &mut Case| {
                        let _ = (&d, &c);
                        field!(@set d c v $($path)+)
                    })
                }) as Box<dyn Fn(f32) -> Patch>,
            )
        };
    }
    let fields: Vec<Field> = vec![
        field!(stretch.stiffness),
        field!(stretch.damping),
        field!(bend.stiffness),
        field!(bend.damping),
        field!(gravity[0]),
        field!(gravity[2]),
        field!(air_drag),
        field!(air_drag_length),
        field!(friction),
        field!(water.r_min),
        field!(water.r_max),
        field!(water.adhesion),
        field!(water_adhesion_length),
        field!(water_pile_cell),
        field!(water.particle_mass),
        field!(water.drag),
        field!(water.wetting_rate),
        field!(water.domain_radius),
        field!(case.water_pos[0]),
        field!(case.water_pos[2]),
        field!(case.water_vel[0]),
        field!(case.water_vel[2]),
        field!(case.head[12]),
        field!(case.head[0]),
        field!(case.dt),
        field!(case.collider.radius),
        field!(case.collider.a[0]),
    ];
    let up = |x: f32| f32::from_bits(x.to_bits() + 1);
    let down = |x: f32| f32::from_bits(x.to_bits() - 1);
    // The neighbours of documented limits: r_max's range, friction's 1, dt's 1 s, and r_max
    // one ulp above r_min.
    let limits = [1e-6f32, 10.0, 1.0, 0.002];
    let mut values: Vec<f32> = HOSTILE.to_vec();
    for l in limits {
        values.extend([down(l), l, up(l)]);
    }
    let mut groom = null_mut();
    unsafe { assert_eq!(wethair_groom_create_paper_scene(16, 6, &mut groom), WETHAIR_OK) };
    let base_case = Case {
        water_pos: [0.0, 0.0, 0.12],
        water_vel: [0.0, 0.0, -1.0],
        head: Mat4::IDENTITY.to_cols_array(),
        dt: 1.0 / 60.0,
        collider: WetHairCollider {
            shape: 0,
            a: [0.0; 3],
            b: [0.0; 3],
            radius: 0.1,
        },
    };
    for backend in backends() {
        let mut d = unsafe {
            let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
            wethair_sim_desc_default(d.as_mut_ptr());
            d.assume_init()
        };
        d.groom = groom;
        d.backend = backend as u32;
        d.collider_count = 1;
        d.water.capacity = 4096;
        let gpu = backend == Backend::GPU;
        for (name, make) in &fields {
            // The GPU runs the extremes only (each case starts a device on lavapipe).
            let vals: &[f32] = if gpu { &HOSTILE[..3] } else { &values };
            for &v in vals {
                unsafe { run_case(&format!("{backend:?} {name} = {v:e}"), d, base_case, &make(v)) };
            }
        }
        // r_max one ulp above r_min, at the paper's radius.
        let ulp: Patch = Box::new(move |d, _| {
            d.water.r_min = 0.002;
            d.water.r_max = up(0.002);
        });
        unsafe { run_case(&format!("{backend:?} r_max one ulp above r_min"), d, base_case, &ulp) };
    }
    unsafe { wethair_groom_destroy(groom) };
}

/// The TressFX 3 ponytail (517 strands of 16 points, centimetres and y up in the file) in
/// metres and z up, 1 g per point as the paper scene's parameters (used below) expect.
fn ponytail() -> wethair::groom::Groom {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ponytail_back.tfx"));
    let opt = wethair::groom::LoadOptions {
        scale: 0.01,
        up_axis: wethair::groom::UpAxis::Y_TO_Z,
        linear_density: 0.0,
        point_mass: 1e-3,
        ..Default::default()
    };
    wethair::groom::load_file_with(path, &opt).unwrap()
}

/// Both clumping measures after `frames` frames, with `particles` placed in the hair.
fn ponytail_clumping(particles: usize, particle_mass: f32, frames: usize) -> (f32, f32, u32) {
    let groom = ponytail();
    let mut params = SimParams {
        backend: Backend::CPU,
        ..SimParams::paper()
    };
    params.water.particle_mass = particle_mass;
    let mut sim = Simulation::new(&groom, params).unwrap();
    // Let the strands settle under gravity first, then wet them where they hang.
    for _ in 0..60 {
        sim.step(1.0 / 60.0).unwrap();
    }
    if particles > 0 {
        let water = wethair::scenes::on_hair(&sim.positions(), particles, &mut Lcg(3));
        sim.add_water(&water, &[]).unwrap();
    }
    for _ in 0..frames {
        sim.step(1.0 / 60.0).unwrap();
    }
    let st = sim.stats();
    (st.clumping, st.clumping_along, st.particles)
}

/// Item 11: on long hair the tips can fan out while the strands bundle along their length;
/// the along-strand measure sees the bundling, and wet long hair measurably clumps by it.
#[test]
fn wet_long_hair_clumps_along_its_strands() {
    let _s = serial();
    // The paper's 1 g particles outweigh the pull of the few points near them in sparse long
    // hair (9.8 mN against at most s = 8 mN per point) and drain out of it: no clumping, the
    // issue's "17% higher wet". Water-density droplets of radius r_min (34 mg) stay and bundle.
    let (_, _, paper_held) = ponytail_clumping(1500, 1e-3, 120);
    assert!(
        paper_held < 150,
        "the paper's particles should drain from sparse hair: {paper_held} held"
    );
    let m = 1000.0 * 4.0 / 3.0 * std::f32::consts::PI * 0.002f32.powi(3);
    let (dry_tip, dry_along, _) = ponytail_clumping(0, m, 240);
    let (wet_tip, wet_along, held) = ponytail_clumping(3000, m, 240);
    eprintln!(
        "ponytail 517 x 16, {m:.2e} kg droplets: {held} of 3000 held; tips dry {dry_tip:.5} wet {wet_tip:.5} m; \
         along the strands dry {dry_along:.5} wet {wet_along:.5} m"
    );
    assert!(held > 1500, "most droplets should stay in the hair: {held} held");
    assert!(
        wet_along < 0.9 * dry_along,
        "along: dry {dry_along} m, wet {wet_along} m"
    );
}
