//! Colliders on bones of their own (`SimParams::collider_frames`; `physics/collide.rs`
//! `ColliderFrames`): frames the host moves exactly as the head give the head's colliders bit
//! for bit (steps, fixed steps inside a frame, a reset, the error estimate's shadow, water, both
//! backends, 1 and 2 threads); a capsule raised and turned on its own frame under still hanging
//! hair lifts the hair and catches falling water, with no free point or particle left inside it
//! after any step, on both backends; a capsule and an SDF slab that slide carry the drops
//! resting on them (colliders answer relative to their own motion); bad frames are refused by
//! name and a refused call changes nothing; C hosts reach all of it, and a 0.9.0 host gets
//! colliders on the head.

use crate::common::{backends, serial};
use glam::{Affine3A, Mat4, Quat, Vec3};
use wethair::groom::paper_scene;
use wethair::{Backend, Error, FixedStep, Shape, SimParams, Simulation};

/// A head sphere and a neck capsule: in head space, or each in its own frame.
fn head_and_neck() -> Vec<Shape> {
    vec![
        Shape::Sphere {
            center: Vec3::ZERO,
            radius: 0.1,
        },
        Shape::Capsule {
            a: Vec3::new(0.0, 0.0, -0.1),
            b: Vec3::new(0.0, 0.03, -0.25),
            radius: 0.045,
        },
    ]
}

/// The head at frame `f`: turning, nodding and swaying (a uniform scale of 1, as a bone).
fn head_at(f: u32) -> Mat4 {
    let t = f as f32 / 60.0;
    Mat4::from_scale_rotation_translation(
        Vec3::ONE,
        Quat::from_rotation_z(0.8 * (3.0 * t).sin()) * Quat::from_rotation_x(0.3 * (2.0 * t).sin()),
        Vec3::new(0.05 * (4.0 * t).sin(), 0.0, 0.02 * t),
    )
}

/// 200 drops in a disc above the head, falling.
fn shower(s: &mut Simulation) {
    let mut rng = wethair::scenes::Lcg(11);
    let pos: Vec<Vec3> = (0..200)
        .map(|_| Vec3::new(rng.next_f32() * 0.2 - 0.1, rng.next_f32() * 0.2 - 0.1, 0.13))
        .collect();
    let vel = vec![Vec3::new(0.0, 0.0, -0.5); pos.len()];
    s.add_water(&pos, &vel).unwrap();
}

/// Bits of every point and particle, and of the error estimate, after 40 frames of the moving
/// head with a reset at frame 20, with 200 drops showered at the start and after the reset
/// (`water`) or none: the colliders follow the head, or (`on_frames`) each is on a frame of its
/// own that the host moves to the head's transform every frame.
fn head_run(backend: Backend, threads: u32, on_frames: bool, fixed: bool, water: bool) -> Vec<u32> {
    let groom = paper_scene(300, 6).unwrap();
    let p = SimParams {
        backend,
        threads,
        colliders: head_and_neck(),
        collider_frames: if on_frames {
            vec![Affine3A::IDENTITY; 2]
        } else {
            Vec::new()
        },
        error_estimate_stride: 16,
        // 1/120 s steps under 1/50 s frames: steps end at fractions of their frame.
        fixed_step: if fixed {
            FixedStep {
                step: 1.0 / 120.0,
                ..FixedStep::OFF
            }
        } else {
            FixedStep::OFF
        },
        ..SimParams::paper()
    };
    let mut s = Simulation::new(&groom, p).unwrap();
    let shower = |s: &mut Simulation| {
        if water {
            shower(s);
        }
    };
    shower(&mut s);
    for f in 1..=40 {
        let m = head_at(f);
        s.set_head_transform(m).unwrap();
        if on_frames {
            for c in 0..2 {
                s.set_collider_transform(c, m).unwrap();
            }
        }
        if f == 20 {
            s.reset().unwrap();
            shower(&mut s);
        }
        if fixed {
            s.advance(1.0 / 50.0).unwrap();
        } else {
            s.step(1.0 / 60.0).unwrap();
        }
    }
    let (drops, _) = s.water().unwrap();
    // The shadow runs the hair without water (with water it withholds its estimate).
    let est = s.stats().error_estimate.map_or(-1.0, |e| e.max);
    assert_eq!(est >= 0.0, !water, "{backend:?}: the shadow's estimate ({est} m)");
    s.positions()
        .iter()
        .chain(&drops)
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .chain([est.to_bits()])
        .collect()
}

#[test]
fn frames_moved_with_the_head_give_the_head_colliders_bits() {
    let _serial = serial();
    for backend in backends() {
        let threads = if backend == Backend::CPU { 2 } else { 0 };
        for (fixed, water) in [(false, false), (false, true), (true, false), (true, true)] {
            let head = head_run(backend, threads, false, fixed, water);
            let frames = head_run(backend, threads, true, fixed, water);
            assert!(
                head == frames,
                "{backend:?}, fixed steps {fixed}, water {water}: colliders on frames moved as the head differ from the head's"
            );
        }
    }
    assert!(
        head_run(Backend::CPU, 1, true, false, true) == head_run(Backend::CPU, 2, true, false, true),
        "collider frames: 1 and 2 threads differ"
    );
}

/// A capsule 0.5 m long along x, 3 cm in radius, in its own frame.
const BAR: Shape = Shape::Capsule {
    a: Vec3::new(-0.25, 0.0, 0.0),
    b: Vec3::new(0.25, 0.0, 0.0),
    radius: 0.03,
};

/// The bar's frame at frame `f`: at z = -0.4 (below the hair, which hangs to z = -0.065)
/// until frame 30, raised to z = -0.05 (its top 2 cm into the hair) and turned 0.5 rad about z
/// by frame 90, then still.
fn bar_at(f: u32, raise: bool) -> Affine3A {
    let a = if raise {
        (f.saturating_sub(30) as f32 / 60.0).min(1.0)
    } else {
        0.0
    };
    Affine3A::from_rotation_translation(Quat::from_rotation_z(0.5 * a), Vec3::new(0.0, 0.0, -0.4 + 0.35 * a))
}

/// How far each point lies inside the bar placed by `t` (0 outside): the worst, and how many
/// points rest on its surface (within 2 mm outside it).
fn inside_bar(points: &[Vec3], t: &Affine3A) -> (f32, usize) {
    let pl = BAR.place(t);
    let (mut worst, mut resting) = (0.0f32, 0);
    for &p in points {
        let u = ((p - pl.a).dot(pl.ab) * pl.inv_len2).clamp(0.0, 1.0);
        let d = (p - (pl.a + pl.ab * u)).length();
        worst = worst.max(pl.radius - d);
        resting += (d >= pl.radius - 1e-4 && d < pl.radius + 2e-3) as usize;
    }
    (worst, resting)
}

/// Where the bar run ends: the lowest hair point over the raised bar's axis (within 1.5 cm
/// across it, in its final place), and the points and particles resting on the bar.
struct BarRun {
    lowest_over_axis: f32,
    hair_on_bar: usize,
    water_on_bar: usize,
}

/// The paper scene's 300 strands hanging from a still head, the bar raised (`raise`) or left
/// below on its own frame, 200 drops let fall along its top at frame 90; 120 frames. Asserts after
/// every step that no free point and no particle is deeper than 10 µm inside the bar.
fn bar_run(backend: Backend, raise: bool) -> BarRun {
    let groom = paper_scene(300, 6).unwrap();
    let p = SimParams {
        backend,
        threads: 2,
        colliders: vec![BAR],
        collider_frames: vec![bar_at(0, raise)],
        ..SimParams::paper()
    };
    let mut s = Simulation::new(&groom, p).unwrap();
    for f in 1..=120 {
        if f == 90 {
            // Over the bar's top, in line with it, where little hair is.
            let mut rng = wethair::scenes::Lcg(5);
            let drops: Vec<Vec3> = (0..200)
                .map(|_| {
                    let u = rng.next_f32() * 0.36 - 0.18;
                    let w = rng.next_f32() * 0.02 - 0.01;
                    let (sin, cos) = 0.5f32.sin_cos();
                    Vec3::new(u * cos - w * sin, u * sin + w * cos, 0.0)
                })
                .collect();
            s.add_water(&drops, &[]).unwrap();
        }
        let t = bar_at(f, raise);
        s.set_collider_transform(0, Mat4::from(t)).unwrap();
        s.step(1.0 / 60.0).unwrap();
        let free: Vec<Vec3> = s
            .positions()
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % 6 != 0)
            .map(|(_, p)| p)
            .collect();
        let (hair_in, _) = inside_bar(&free, &t);
        let (water_in, _) = inside_bar(&s.water().unwrap().0, &t);
        assert!(
            hair_in < 1e-5 && water_in < 1e-5,
            "{backend:?}, frame {f}: a point {hair_in} m, a particle {water_in} m inside the bar"
        );
    }
    let x = s.positions();
    let end = bar_at(120, raise);
    let (_, hair_on_bar) = inside_bar(&x, &end);
    let (_, water_on_bar) = inside_bar(&s.water().unwrap().0, &end);
    let over = bar_at(120, true).inverse();
    BarRun {
        lowest_over_axis: x
            .iter()
            .filter(|p| {
                let q = over.transform_point3(**p);
                q.x.abs() < 0.25 && q.y.abs() < 0.015
            })
            .map(|p| p.z)
            .fold(f32::INFINITY, f32::min),
        hair_on_bar,
        water_on_bar,
    }
}

#[test]
fn a_capsule_on_its_own_frame_lifts_still_hair_and_catches_water() {
    let _serial = serial();
    for backend in backends() {
        let still = bar_run(backend, false);
        let raised = bar_run(backend, true);
        eprintln!(
            "{backend:?}: lowest hair over the raised bar's axis at z {:.4} m with the bar left below, {:.4} raised; {} points and {} particles rest on it",
            still.lowest_over_axis, raised.lowest_over_axis, raised.hair_on_bar, raised.water_on_bar
        );
        assert_eq!(still.hair_on_bar, 0, "{backend:?}: no hair reaches the bar left below");
        // The raised bar's centre ends at z = -0.05; 1.5 cm across its axis its top is at
        // -0.05 + sqrt(0.03² - 0.015²) = -0.024 m.
        assert!(
            still.lowest_over_axis < -0.05 + 0.026 - 0.01,
            "{backend:?}: hair hangs 1 cm into where the bar is raised to ({})",
            still.lowest_over_axis
        );
        assert!(
            raised.lowest_over_axis > -0.05 + 0.026 - 1e-4,
            "{backend:?}: the raised bar lifts the hair over it ({})",
            raised.lowest_over_axis
        );
        assert!(
            raised.hair_on_bar > 50,
            "{backend:?}: {} points rest on the bar",
            raised.hair_on_bar
        );
        assert!(
            raised.water_on_bar > 20,
            "{backend:?}: {} drops rest on the bar",
            raised.water_on_bar
        );
    }
}

#[test]
fn bad_frames_are_refused_by_name_and_change_nothing() {
    let groom = paper_scene(20, 6).unwrap();
    let params = |frames: Vec<Affine3A>| SimParams {
        backend: Backend::CPU,
        colliders: head_and_neck(),
        collider_frames: frames,
        ..SimParams::paper()
    };
    for (frames, want) in [
        (vec![Affine3A::IDENTITY], "1 collider frames for 2 colliders"),
        (
            vec![Affine3A::IDENTITY, Affine3A::from_scale(Vec3::new(1.0, 2.0, 1.0))],
            "collider 1's frame: transform must be a rotation, translation and uniform scale",
        ),
        (
            vec![Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)), Affine3A::IDENTITY],
            "collider 0's frame: transform is singular or mirrored",
        ),
        (
            vec![
                Affine3A::from_translation(Vec3::new(f32::NAN, 0.0, 0.0)),
                Affine3A::IDENTITY,
            ],
            "collider 0's frame: transform has a non-finite entry",
        ),
    ] {
        match Simulation::new(&groom, params(frames)) {
            Err(Error::InvalidArgument(m)) => assert!(m.contains(want), "{m}"),
            other => panic!("{want}: {other:?}"),
        }
    }
    // A refused transform leaves the target where it was: the next steps are those of a
    // simulation that never saw the call.
    let run = |refused: bool| {
        let mut s = Simulation::new(&groom, params(vec![Affine3A::IDENTITY; 2])).unwrap();
        let up = Mat4::from_translation(Vec3::new(0.0, 0.0, 0.05));
        s.set_collider_transform(1, up).unwrap();
        if refused {
            for (i, m, want) in [
                (1, Mat4::from_scale(Vec3::new(1.0, 1.0, 3.0)), "uniform scale"),
                (1, Mat4::from_cols_array(&[f32::NAN; 16]), "last row"),
                (0, Mat4::ZERO, "last row"),
                (2, Mat4::IDENTITY, "collider index 2: the simulation has 2 colliders"),
            ] {
                match s.set_collider_transform(i, m) {
                    Err(Error::InvalidArgument(e)) => assert!(e.contains(want), "{e}"),
                    other => panic!("{want}: {other:?}"),
                }
            }
        }
        for _ in 0..10 {
            s.step(1.0 / 60.0).unwrap();
        }
        s.positions()
    };
    assert_eq!(run(true), run(false), "a refused call changed the simulation");
    // Colliders on the head take no frame.
    let mut s = Simulation::new(&groom, params(Vec::new())).unwrap();
    match s.set_collider_transform(0, Mat4::IDENTITY) {
        Err(Error::Unsupported(m)) => assert!(m.contains("collider_frames"), "{m}"),
        other => panic!("a head collider took a frame: {other:?}"),
    }
}

mod c_abi {
    //! Collider frames through the C ABI: `WetHairSimDesc::collider_frames`,
    //! `wethair_sim_set_collider_transform`; a 368-byte (0.9.0) desc gets colliders on the head.

    use std::ptr::null_mut;
    use wethair::ffi::*;
    use WetHairResult::*;

    use crate::common::last_error;

    const IDENTITY: [f32; 16] = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.];

    /// A simulation of 50 paper strands with one sphere, made with a desc of `size` bytes whose
    /// frames point at `frames` (or NULL).
    fn make(size: u32, frames: Option<&[f32]>) -> (WetHairResult, *mut WetHairSim, *mut WetHairGroom) {
        let mut g = null_mut();
        assert_eq!(unsafe { wethair_groom_create_paper_scene(50, 6, &mut g) }, WETHAIR_OK);
        let ball = WetHairCollider {
            shape: WetHairColliderType::WETHAIR_COLLIDER_SPHERE as u32,
            a: [0.0, 0.0, -0.3],
            b: [0.0; 3],
            radius: 0.05,
        };
        let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
        assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
        let mut d = unsafe { d.assume_init() };
        d.struct_size = size;
        assert!(d.collider_frames.is_null(), "none by default");
        d.groom = g;
        d.backend = wethair::Backend::CPU as u32;
        d.colliders = &ball;
        d.collider_count = 1;
        d.collider_frames = frames.map_or(std::ptr::null(), |f| f.as_ptr());
        let mut s = null_mut();
        let r = unsafe { wethair_sim_create(&d, &mut s) };
        (r, s, g)
    }

    #[test]
    fn collider_frames_reach_c_hosts() {
        let full = std::mem::size_of::<WetHairSimDesc>() as u32;
        assert_eq!(full, 376);
        let (r, s, g) = make(full, Some(&IDENTITY));
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        let mut up = IDENTITY;
        up[14] = 0.1;
        assert_eq!(
            unsafe { wethair_sim_set_collider_transform(s, 0, up.as_ptr()) },
            WETHAIR_OK
        );
        assert_eq!(unsafe { wethair_sim_step(s, 1.0 / 60.0) }, WETHAIR_OK);
        let mut squashed = IDENTITY;
        squashed[10] = 0.5;
        for (index, m, code, name) in [
            (0, squashed.as_ptr(), WETHAIR_ERROR_INVALID_ARGUMENT, "uniform scale"),
            (1, IDENTITY.as_ptr(), WETHAIR_ERROR_INVALID_ARGUMENT, "collider index 1"),
            (0, std::ptr::null(), WETHAIR_ERROR_NULL_POINTER, "matrix"),
            (0, IDENTITY.as_ptr(), WETHAIR_OK, ""),
        ] {
            assert_eq!(
                unsafe { wethair_sim_set_collider_transform(s, index, m) },
                code,
                "{index}"
            );
            if code != WETHAIR_OK {
                assert!(last_error().contains(name), "{}", last_error());
            }
        }
        assert_eq!(
            unsafe { wethair_sim_set_collider_transform(null_mut(), 0, IDENTITY.as_ptr()) },
            WETHAIR_ERROR_NULL_POINTER
        );
        unsafe { wethair_sim_destroy(s) };
        unsafe { wethair_groom_destroy(g) };
        // A bad frame at create is refused by name, and no simulation is made.
        let mut mirrored = IDENTITY;
        mirrored[0] = -1.0;
        let (r, s, g) = make(full, Some(&mirrored));
        assert_eq!((r, s.is_null()), (WETHAIR_ERROR_INVALID_ARGUMENT, true));
        assert!(last_error().contains("collider 0's frame"), "{}", last_error());
        unsafe { wethair_groom_destroy(g) };
        // A 0.9.0 host's 368-byte desc ends before the field: its colliders follow the head,
        // whatever lies past its size.
        let (r, s, g) = make(368, Some(&mirrored));
        assert_eq!(r, WETHAIR_OK, "{}", last_error());
        assert_eq!(
            unsafe { wethair_sim_set_collider_transform(s, 0, IDENTITY.as_ptr()) },
            WETHAIR_ERROR_UNSUPPORTED
        );
        unsafe { wethair_sim_destroy(s) };
        unsafe { wethair_groom_destroy(g) };
    }
}

/// Where 20 drops resting on a collider end after it slides 0.15 m along x: the collider
/// (`field`: an SDF slab, else the bar) sits at z = -0.35, far below the hair, still for 30
/// frames while the drops settle on its top, then moves at 0.3 m/s for 30 frames. Returns the
/// drops' mean travel along x over the slide and their mean height over the top.
fn slide(backend: Backend, field: bool) -> (f32, f32) {
    use std::sync::Arc;
    use wethair::physics::sdf::Sdf;
    let groom = paper_scene(20, 6).unwrap();
    let at = |f: u32| Affine3A::from_translation(Vec3::new(0.3 * (f.saturating_sub(30) as f32 / 60.0), 0.0, -0.35));
    let (colliders, collider_frames, sdfs, top) = if field {
        // 4 cm thick (|z| < 0.02 in its frame), 40 cm square: its top at -0.33.
        let slab = Sdf::from_fn([41, 41, 9], Vec3::new(-0.2, -0.2, -0.04), 0.01, |p| p.z.abs() - 0.02);
        let slab = Sdf {
            transform: at(0),
            ..slab
        };
        (vec![], vec![], vec![Arc::new(slab)], -0.33)
    } else {
        (vec![BAR], vec![at(0)], vec![], -0.35 + 0.03)
    };
    let mut p = SimParams {
        backend,
        threads: 2,
        colliders,
        collider_frames,
        sdfs,
        ..SimParams::paper()
    };
    p.water.domain_radius = 1.0; // the default keeps drops within the groom's reach
    let mut s = Simulation::new(&groom, p).unwrap();
    let drops: Vec<Vec3> = (0..20)
        .map(|i| Vec3::new(-0.1 + 0.01 * i as f32, 0.0, top + 0.003))
        .collect();
    s.add_water(&drops, &[]).unwrap();
    let mean = |s: &Simulation| {
        let (w, _) = s.water().unwrap();
        assert_eq!(w.len(), 20, "{backend:?}: every drop stays");
        w.iter().fold(Vec3::ZERO, |a, p| a + *p) / w.len() as f32
    };
    let mut before = Vec3::ZERO;
    for f in 1..=60 {
        let m = Mat4::from(at(f));
        if field {
            s.set_sdf_transform(0, m).unwrap();
        } else {
            s.set_collider_transform(0, m).unwrap();
        }
        s.step(1.0 / 60.0).unwrap();
        if f == 30 {
            before = mean(&s);
        }
    }
    let after = mean(&s);
    (after.x - before.x, after.z - top)
}

#[test]
fn a_moving_collider_carries_what_rests_on_it() {
    let _serial = serial();
    for backend in backends() {
        for field in [false, true] {
            let (travel, height) = slide(backend, field);
            let what = if field { "SDF slab" } else { "capsule" };
            eprintln!(
                "{backend:?}, {what}: drops travelled {travel:.4} m of the collider's 0.15, {height:.4} m over its top"
            );
            // Friction takes a fifth of the drop's velocity relative to the surface each
            // substep in contact: it catches up within a few substeps and rides along. A
            // surface answered as still would slide from under it (travel about 0).
            assert!(
                travel > 0.13 && travel < 0.16,
                "{backend:?}, {what}: the drops travelled {travel} m"
            );
            assert!(
                height.abs() < 0.005,
                "{backend:?}, {what}: the drops are {height} m off the top"
            );
        }
    }
}
