//! SDF colliders (issue 17, item 3; `physics/sdf.rs`): a sampled sphere holds hair as the
//! analytic sphere does, within a cell; no point ends a step more than the documented depth
//! inside any field; a field moved by its transform pushes hair and water; results are the
//! same on any thread count and run after run on the GPU; the GPU pushes as the CPU does,
//! point by point where the scene is not chaotic and by what the scene does where it is; bad
//! grids and transforms are refused by name.

use crate::common::{backends, max_diff, nudged_groom, serial};
use glam::{Affine3A, Mat4, Quat, Vec3};
use std::sync::Arc;
use wethair::groom::Groom;
use wethair::physics::sdf::{PlacedSdf, Sdf};
use wethair::{Backend, Error, Shape, SimParams, Simulation};

/// The documented depth, in cells, a free point may end a step inside a field: the push is a
/// Newton step to the trilinear zero level, exact where the field is linear over the cell.
const DEPTH_CELLS: f32 = 0.05;

/// A sphere of `radius` at the origin sampled every `cell` over a box 2 cells wider than it.
fn sphere(radius: f32, cell: f32) -> Sdf {
    let half = radius + 2.0 * cell;
    let n = (2.0 * half / cell).ceil() as u32 + 1;
    Sdf::from_fn([n; 3], Vec3::splat(-half), cell, |p| p.length() - radius)
}

/// 300 strands of the paper scene (roots on a 0.1 m head), symplectic Euler, on the CPU.
fn scene(colliders: Vec<Shape>, sdfs: Vec<Sdf>, threads: u32) -> Simulation {
    scene_on(Backend::CPU, colliders, sdfs, threads)
}

/// The same scene on `backend`.
fn scene_on(backend: Backend, colliders: Vec<Shape>, sdfs: Vec<Sdf>, threads: u32) -> Simulation {
    let groom = wethair::groom::paper_scene(300, 6).unwrap();
    scene_with(&groom, backend, colliders, sdfs, threads)
}

/// The scene's settings on `groom`.
fn scene_with(groom: &Groom, backend: Backend, colliders: Vec<Shape>, sdfs: Vec<Sdf>, threads: u32) -> Simulation {
    let p = SimParams {
        backend,
        threads,
        colliders,
        sdfs: sdfs.into_iter().map(Arc::new).collect(),
        ..SimParams::paper()
    };
    Simulation::new(groom, p).unwrap()
}

/// The deepest a free point of `s` lies inside `sdf` placed by `t`, in cells (0 when none is;
/// the roots, pinned on the head, are skipped).
fn deepest(s: &Simulation, sdf: &Sdf, t: &Affine3A) -> f32 {
    let at = PlacedSdf::new(sdf, t);
    let mut worst = 0.0f32;
    for (i, x) in s.positions().iter().enumerate() {
        if i % 6 == 0 {
            continue;
        }
        if let Some((d, _)) = sdf.sample(at.to_grid.transform_point3(*x)) {
            worst = worst.max(-d / sdf.cell);
        }
    }
    worst
}

#[test]
fn a_sampled_sphere_pushes_out_as_the_analytic_sphere_does_within_a_cell() {
    use wethair::physics::collide::{collide_point, Shape as S};
    use wethair::physics::sdf::collide_sdf_point;
    let cell = 0.01;
    let field = sphere(0.1, cell);
    let ball = S::Sphere {
        center: Vec3::ZERO,
        radius: 0.1,
    }
    .place(&Affine3A::IDENTITY);
    let at = PlacedSdf::new(&field, &Affine3A::IDENTITY);
    // 10,000 points from a tenth of a cell to two cells deep (nearer the surface, the
    // trilinear zero level and the sphere may disagree on whether a point is inside at all),
    // moving every way: the same place and velocity out.
    let mut rng = wethair::scenes::Lcg(9);
    let (mut dx, mut dv) = (0.0f32, 0.0f32);
    for _ in 0..10_000 {
        let dir = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5).normalize();
        let p = dir * (0.1 - cell * (0.1 + 1.9 * rng.next_f32()));
        let v = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5);
        let (mut xa, mut va) = (p, v);
        collide_point(&mut xa, &mut va, &ball, 0.2);
        let (mut xs, mut vs) = (p, v);
        collide_sdf_point(&mut xs, &mut vs, &field, &at, 0.2);
        dx = dx.max((xa - xs).length());
        dv = dv.max((va - vs).length() / v.length().max(1e-3));
    }
    assert!(dx < cell, "pushed {dx:e} m from the analytic sphere's point");
    // Measured: 0.15 of a cell (the trilinear gradient turns a few degrees at cell faces,
    // and a point two cells deep moves two cells along it).
    assert!(dx < 0.25 * cell, "pushed {dx:e} m away");
    eprintln!(
        "sampled against analytic sphere: {:.3} cells, velocity {dv:.4} relative",
        dx / cell
    );
    assert!(dv < 0.1, "velocity {dv} (relative) from the analytic response");
    // Hair on the head: the first 10 frames agree within a cell (later a strand standing on
    // the pole falls one way or the other, and the two runs part), and over 90 frames no free
    // point ends a step deeper than the documented depth.
    let mut analytic = scene(
        vec![S::Sphere {
            center: Vec3::ZERO,
            radius: 0.1,
        }],
        vec![],
        2,
    );
    let mut sampled = scene(vec![], vec![field.clone()], 2);
    let mut worst = 0.0f32;
    for f in 0..90 {
        analytic.step(1.0 / 60.0).unwrap();
        sampled.step(1.0 / 60.0).unwrap();
        worst = worst.max(deepest(&sampled, &field, &Affine3A::IDENTITY));
        if f < 10 {
            let (a, b) = (analytic.positions(), sampled.positions());
            let gap = a.iter().zip(&b).map(|(p, q)| (*p - *q).length()).fold(0.0, f32::max);
            assert!(
                gap < cell,
                "frame {f}: the hair is {gap:e} m from the analytic sphere's"
            );
        }
    }
    assert!(worst <= DEPTH_CELLS, "a point ended {worst} cells inside the field");
    let b = sampled.positions();
    let low = b.iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
    assert!(low < 0.0, "hair fell below the head's equator ({low})");
}

/// A slab 4 cm thick (|z| < 0.02 in its frame), 40 cm wide, rotated and scaled by 1.5 and
/// raised from z = -0.3 to -0.05 under the hanging hair over 120 frames, with 200 drops
/// falling onto it; returns where hair and water end after 150 frames. Asserts on the way that
/// no point ends a step deeper than the documented depth, and at the end that hair and water
/// rest on the slab's top face and no particle is inside it.
fn moving_slab(groom: &Groom, backend: Backend) -> SlabStats {
    let cell = 0.01;
    let field = Sdf::from_fn([41, 41, 9], Vec3::new(-0.2, -0.2, -0.04), cell, |p| p.z.abs() - 0.02);
    let place = |z: f32| {
        Affine3A::from_scale_rotation_translation(Vec3::splat(1.5), Quat::from_rotation_z(0.3), Vec3::new(0.0, 0.0, z))
    };
    let mut s = scene_with(groom, backend, vec![], vec![field.clone()], 2);
    s.set_sdf_transform(0, Mat4::from(place(-0.3))).unwrap();
    s.reset().unwrap(); // reset puts the field where it was last set
    let mut rng = wethair::scenes::Lcg(3);
    let drops: Vec<Vec3> = (0..200)
        .map(|_| Vec3::new(rng.next_f32() * 0.3 - 0.15, rng.next_f32() * 0.3 - 0.15, -0.15))
        .collect();
    s.add_water(&drops, &[]).unwrap();
    let mut worst = 0.0f32;
    for f in 0..150 {
        let z = -0.3 + 0.25 * (f.min(119) as f32 / 119.0);
        s.set_sdf_transform(0, Mat4::from(place(z))).unwrap();
        s.step(1.0 / 60.0).unwrap();
        worst = worst.max(deepest(&s, &field, &place(z)));
    }
    assert!(
        worst <= DEPTH_CELLS,
        "{backend:?}: a point ended {worst} cells inside the moving slab"
    );
    // The slab's top face ends at z = -0.05 + 1.5 * 0.02 = -0.02, above the hanging tips:
    // hair and water rest on it.
    let top = -0.05 + 1.5 * 0.02;
    let hair = s.positions();
    let on_top = hair.iter().filter(|p| (p.z - top).abs() < 5e-3).count();
    assert!(on_top > 100, "{backend:?}: {on_top} hair points rest on the slab");
    let (water, _) = s.water().unwrap();
    let inside = water
        .iter()
        .filter(|p| p.x.abs() < 0.2 && p.y.abs() < 0.2 && p.z < top - 1.5 * DEPTH_CELLS * cell && p.z > -0.18)
        .count();
    assert_eq!(inside, 0, "{backend:?}: particles inside the slab");
    assert!(
        water.iter().any(|p| (p.z - top).abs() < 0.01),
        "{backend:?}: particles rest on the slab"
    );
    SlabStats { hair, water, on_top }
}

/// Where a moving slab run ended.
struct SlabStats {
    hair: Vec<Vec3>,
    water: Vec<Vec3>,
    /// Hair points resting on the slab's top face.
    on_top: usize,
}

impl SlabStats {
    const NAMES: [&'static str; 7] = [
        "hair points on top",
        "hair mean x",
        "hair mean y",
        "hair mean z",
        "water mean x",
        "water mean y",
        "water mean z",
    ];

    /// The statistics compared across backends, in `NAMES`' order.
    fn stats(&self) -> [f32; 7] {
        let mean = |w: &[Vec3]| w.iter().fold(Vec3::ZERO, |a, p| a + *p) / w.len().max(1) as f32;
        let (h, w) = (mean(&self.hair), mean(&self.water));
        [self.on_top as f32, h.x, h.y, h.z, w.x, w.y, w.z]
    }
}

#[test]
fn a_moving_field_pushes_hair_and_water_and_follows_its_transform() {
    let _serial = serial();
    let groom = wethair::groom::paper_scene(300, 6).unwrap();
    let runs: Vec<_> = backends().into_iter().map(|b| moving_slab(&groom, b)).collect();
    let [cpu, gpu] = &runs[..] else {
        return;
    };
    // The GPU against the CPU. Hair standing on the slab buckles one way or the other: a
    // sideways nudge of 1e-7 m moves the CPU's own hair up to centimetres by the end, and an
    // H100's rounding does the same (its hair 3e-8 m off the CPU's after one frame, 6 mm by
    // frame 60, whether the slab moves or not). So here the two are compared by what the
    // scene does, each statistic within the spread of five nudged CPU runs widened by that
    // spread again; pointwise parity of the SDF pass is `the_gpu_pushes_as_the_cpu_does`.
    let band: Vec<[f32; 7]> = (1..=5)
        .map(|seed| moving_slab(&nudged_groom(&groom, seed), Backend::CPU).stats())
        .collect();
    let (c, g) = (cpu.stats(), gpu.stats());
    for k in 0..c.len() {
        let lo = band.iter().map(|b| b[k]).fold(c[k], f32::min);
        let hi = band.iter().map(|b| b[k]).fold(c[k], f32::max);
        let w = hi - lo;
        eprintln!(
            "moving slab, {}: CPU {:.4e}, nudged CPU {lo:.4e}..{hi:.4e}, GPU {:.4e}",
            SlabStats::NAMES[k],
            c[k],
            g[k]
        );
        assert!(
            g[k] >= lo - w && g[k] <= hi + w,
            "{}: GPU {} outside the nudged CPU runs' {lo}..{hi} widened by {w}",
            SlabStats::NAMES[k],
            g[k]
        );
    }
    assert_eq!(cpu.water.len(), gpu.water.len(), "the same particles on both backends");
}

/// A curtain of 40 hanging strands that a sampled sphere, placed by a transform that scales,
/// turns and slides it, pushes aside across 60 frames: hair pushed by a convex body does not
/// buckle, so a GPU that pushes as the CPU does ends within rounding of it point by point.
/// (Hair standing on the head sphere is no such case: strands near its pole fall one way or
/// the other, and a 1e-7 m nudge grows to 1e-5 m in 10 frames.)
#[test]
fn the_gpu_pushes_as_the_cpu_does() {
    let _serial = serial();
    let mass = wethair::groom::paper_scene(1, 6).unwrap().masses()[1];
    let pos: Vec<Vec3> = (0..40)
        .flat_map(|i| (0..6).map(move |k| Vec3::new(-0.1025 + 0.005 * i as f32, 0.0, -0.02 * k as f32)))
        .collect();
    let groom = Groom::new(pos, &[6; 40], None, None, mass).unwrap();
    // A 0.024 m sphere scaled by 1.25 (0.03 m) turns, which a sphere shows only in the
    // arithmetic, and slides from 8 cm in front of the curtain to 1 cm behind its plane.
    let field = sphere(0.024, 0.006);
    let place = |f: u32| {
        let a = f as f32 / 59.0;
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1.25),
            Quat::from_rotation_z(0.5 * a) * Quat::from_rotation_x(0.2),
            Vec3::new(0.0, -0.08 + 0.09 * a, -0.07),
        )
    };
    let run = |g: &Groom, backend: Backend| {
        // Without friction: the turning sphere's surface moves across the hair, and friction
        // would drag the hair along it, turning a 1e-7 m nudge into 0.7 mm (measured); the
        // push and the surface's normal velocity are what this compares point by point.
        let p = SimParams {
            backend,
            threads: 2,
            sdfs: vec![Arc::new(field.clone())],
            friction: 0.0,
            ..SimParams::paper()
        };
        let mut s = Simulation::new(g, p).unwrap();
        s.set_sdf_transform(0, place(0)).unwrap();
        s.reset().unwrap();
        for f in 0..60 {
            s.set_sdf_transform(0, place(f)).unwrap();
            s.step(1.0 / 60.0).unwrap();
        }
        s.positions()
    };
    let c = run(&groom, Backend::CPU);
    // Points struck by the moving sphere take its surface's velocity into them, and leave it
    // faster than a still surface would let them: a 1e-7 m nudge grows to 1.1e-4 m in 60
    // frames (measured, 2026-12-03; 1e-5 m when the surface answered as still). Sensitive,
    // not chaotic.
    let floor = (1..=3)
        .map(|seed| max_diff(&run(&nudged_groom(&groom, seed), Backend::CPU), &c))
        .fold(0.0, f32::max);
    assert!(
        floor < 5e-4,
        "the scene amplifies a 1e-7 m nudge to {floor} m: not a pointwise case"
    );
    let pushed = c.iter().map(|p| p.y).fold(0.0, f32::max);
    assert!(pushed > 0.02, "the field pushes the curtain {pushed} m");
    if backends().contains(&Backend::GPU) {
        let g = run(&groom, Backend::GPU);
        let gap = max_diff(&g, &c);
        // Measured: lavapipe 0 (its arithmetic is the CPU's), an H100 3.6e-8 m.
        eprintln!("SDF parity: GPU {gap:e} m from the CPU, nudged CPU {floor:e} m, pushed {pushed} m");
        assert!(gap < (4.0 * floor).max(1e-5), "GPU hair {gap} m from the CPU's");
    }
}

#[test]
fn sdfs_give_the_same_bits_on_any_thread_count_and_run_after_run() {
    let _serial = serial();
    let field = sphere(0.1, 0.012);
    let bits =
        |s: &Simulation| -> Vec<[u32; 3]> { s.positions().iter().map(|p| p.to_array().map(f32::to_bits)).collect() };
    let run = |backend: Backend, threads: u32| {
        let mut s = scene_on(backend, vec![], vec![field.clone()], threads);
        for _ in 0..30 {
            s.step(1.0 / 60.0).unwrap();
        }
        assert!(
            s.passes().contains(&wethair::plan::Pass::Collide),
            "an SDF alone runs the collide pass"
        );
        bits(&s)
    };
    assert!(run(Backend::CPU, 1) == run(Backend::CPU, 2), "CPU, 1 and 2 threads");
    if backends().contains(&Backend::GPU) {
        assert!(run(Backend::GPU, 0) == run(Backend::GPU, 0), "GPU, run after run");
    }
}

#[test]
fn bad_grids_and_transforms_are_refused_by_name() {
    let groom = wethair::groom::paper_scene(20, 6).unwrap();
    let good = sphere(0.1, 0.02);
    let mut nan = good.clone();
    nan.values[17] = f32::NAN;
    let mut flat = good.clone();
    flat.dims = [1, 15, 15];
    let mut short = good.clone();
    short.values.pop();
    let mut zero_cell = good.clone();
    zero_cell.cell = 0.0;
    let mut huge = good.clone();
    huge.dims = [4096, 4096, 4096];
    let mut stretched = good.clone();
    stretched.transform = Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0));
    let mut mirrored = good.clone();
    mirrored.transform = Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    for (sdfs, want) in [
        (vec![nan], "value 17"),
        (vec![flat], "dims"),
        (vec![short], "values for dims"),
        (vec![zero_cell], "cell"),
        (vec![huge], "samples exceed"),
        (vec![stretched], "uniform scale"),
        (vec![mirrored], "mirrored"),
        (vec![good.clone(); 17], "at most 16"),
    ] {
        let p = SimParams {
            backend: Backend::CPU,
            sdfs: sdfs.into_iter().map(Arc::new).collect(),
            ..SimParams::paper()
        };
        match Simulation::new(&groom, p) {
            Err(Error::InvalidArgument(m) | Error::Capacity(m)) => assert!(m.contains(want), "{m}"),
            other => panic!("{want}: {other:?}"),
        }
    }
    let mut s = scene(vec![], vec![good.clone()], 1);
    let before = s.positions();
    for (m, want) in [
        (Mat4::from_scale(Vec3::new(1.0, 1.0, 3.0)), "uniform scale"),
        (Mat4::from_cols_array(&[f32::NAN; 16]), "last row"),
        (Mat4::ZERO, "last row"),
    ] {
        match s.set_sdf_transform(0, m) {
            Err(Error::InvalidArgument(e)) => assert!(e.contains(want), "{e}"),
            other => panic!("{want}: {other:?}"),
        }
    }
    assert!(matches!(
        s.set_sdf_transform(1, Mat4::IDENTITY),
        Err(Error::InvalidArgument(_))
    ));
    assert_eq!(s.positions(), before);
}

mod c_abi {
    //! SDF colliders through the C ABI: `WetHairSimDesc::sdfs`, `wethair_sim_set_sdf_transform`.

    use std::ptr::null_mut;
    use wethair::ffi::*;
    use WetHairResult::*;

    use crate::common::last_error;

    const IDENTITY: [f32; 16] = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.];

    #[test]
    fn sdf_colliders_reach_c_hosts() {
        let field = super::sphere(0.1, 0.02);
        let mut g = null_mut();
        assert_eq!(unsafe { wethair_groom_create_paper_scene(50, 6, &mut g) }, WETHAIR_OK);
        let sdf = WetHairSdf {
            dims: field.dims,
            origin: field.origin.to_array(),
            cell_size: field.cell,
            reserved: 0,
            values: field.values.as_ptr(),
            transform: IDENTITY,
        };
        let make = |edit: &dyn Fn(&mut WetHairSimDesc, &mut WetHairSdf)| {
            let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
            let size = std::mem::size_of::<WetHairSimDesc>() as u32;
            assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
            let mut d = unsafe { d.assume_init() };
            assert_eq!((d.sdfs, d.sdf_count), (std::ptr::null(), 0), "none by default");
            let mut one = sdf;
            d.groom = g;
            d.backend = wethair::Backend::CPU as u32;
            d.sdf_count = 1;
            edit(&mut d, &mut one);
            d.sdfs = &one;
            let mut s = null_mut();
            let r = unsafe { wethair_sim_create(&d, &mut s) };
            (r, s)
        };
        let (r, s) = make(&|_, _| {});
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let mut up = IDENTITY;
        up[14] = 0.01;
        assert_eq!(unsafe { wethair_sim_set_sdf_transform(s, 0, up.as_ptr()) }, WETHAIR_OK);
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let mut squashed = IDENTITY;
        squashed[10] = 0.5;
        for (index, m, code) in [
            (0, squashed.as_ptr(), WETHAIR_ERROR_INVALID_ARGUMENT),
            (1, IDENTITY.as_ptr(), WETHAIR_ERROR_INVALID_ARGUMENT),
            (0, std::ptr::null(), WETHAIR_ERROR_NULL_POINTER),
        ] {
            assert_eq!(unsafe { wethair_sim_set_sdf_transform(s, index, m) }, code, "{index}");
        }
        unsafe { wethair_sim_destroy(s) };
        type Edit = fn(&mut WetHairSimDesc, &mut WetHairSdf);
        let cases: [(Edit, WetHairResult, &str); 5] = [
            (|d, _| d.sdf_count = 17, WETHAIR_ERROR_CAPACITY, "sdf_count"),
            (|_, s| s.values = std::ptr::null(), WETHAIR_ERROR_NULL_POINTER, "values"),
            (|_, s| s.dims = [100_000, 100_000, 2], WETHAIR_ERROR_CAPACITY, "samples"),
            (|_, s| s.cell_size = f32::NAN, WETHAIR_ERROR_INVALID_ARGUMENT, "cell"),
            (|_, s| s.transform[3] = 1.0, WETHAIR_ERROR_INVALID_ARGUMENT, "last row"),
        ];
        for (edit, code, name) in cases {
            let (r, s) = make(&|d, one| edit(d, one));
            assert_eq!((r, s.is_null()), (code, true), "{name}: {}", last_error());
            assert!(last_error().contains(name), "{}", last_error());
        }
        unsafe { wethair_groom_destroy(g) };
    }
}
