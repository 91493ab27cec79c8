//! Emitters (issue 14, item 9; docs/WET_MODEL.md §9): rain adds `floor(rate t)` drops by time
//! `t`, inside its rectangle, falling at its speed; a spray's drops leave within its cone at
//! its speed, spread over it; the same drops on every run and every thread count; the particle
//! capacity is never exceeded; bad emitters are refused by name; the C calls do the same.

use glam::Vec3;
use wethair::emit::{Emitter, Rain, Spray};
use wethair::groom::paper_scene;
use wethair::{Backend, SimParams, Simulation};

const DT: f32 = 1.0 / 60.0;

fn rain() -> Rain {
    Rain {
        center: Vec3::new(0.0, 0.0, 0.6),
        size: [0.3, 0.2],
        rate: 250.0,
        speed: 3.0,
        seed: 5,
    }
}

fn spray() -> Spray {
    Spray {
        origin: Vec3::new(0.4, 0.0, 0.15),
        direction: Vec3::new(-1.0, 0.0, 0.2),
        half_angle: 0.25,
        rate: 400.0,
        speed: 2.5,
        seed: 8,
    }
}

fn sim(threads: u32) -> Simulation {
    let groom = paper_scene(200, 6).unwrap();
    let mut p = SimParams {
        backend: Backend::CPU,
        threads,
        ..SimParams::paper()
    };
    p.water.domain_radius = 10.0; // nothing leaves while counted
    Simulation::new(&groom, p).unwrap()
}

#[test]
fn rain_falls_at_its_rate_inside_its_rectangle() {
    let mut s = sim(1);
    s.set_rain(Some(rain())).unwrap();
    for f in 1..=90 {
        s.step(DT).unwrap();
        let want = (250.0f64 * (f as f64 * DT as f64)).floor() as u32;
        assert_eq!(s.stats().particles, want, "frame {f}");
    }
    // Each drop number is a pure function of the seed: placed inside the rectangle.
    let e = Emitter::Rain(rain());
    let mut mean = Vec3::ZERO;
    for k in 0..10_000 {
        let (x, v) = e.drop(k);
        assert!((x.x.abs() <= 0.15) && (x.y.abs() <= 0.1) && x.z == 0.6, "{x}");
        assert_eq!(v, Vec3::new(0.0, 0.0, -3.0));
        mean += x / 10_000.0;
    }
    assert!(
        mean.truncate().length() < 0.005,
        "spread over the rectangle: mean {mean}"
    );
    // Stopping the rain stops the drops.
    s.set_rain(None).unwrap();
    let n = s.stats().particles;
    s.step(DT).unwrap();
    assert_eq!(s.stats().particles, n);
}

#[test]
fn a_spray_leaves_within_its_cone_at_its_speed() {
    let e = Emitter::Spray(spray());
    let axis = spray().direction.normalize();
    let mut mean = Vec3::ZERO;
    let mut widest = 0.0f32;
    for k in 0..10_000 {
        let (x, v) = e.drop(k);
        assert_eq!(x, spray().origin);
        assert!((v.length() - 2.5).abs() < 1e-5);
        let angle = v.normalize().dot(axis).clamp(-1.0, 1.0).acos();
        assert!(angle <= 0.25 + 1e-4, "drop {k} at {angle} rad");
        widest = widest.max(angle);
        mean += v.normalize() / 10_000.0;
    }
    assert!(widest > 0.24, "reaches the cone's edge: {widest}");
    assert!(mean.normalize().dot(axis) > 0.9999, "centred on the axis");
    let mut s = sim(1);
    s.set_spray(Some(spray())).unwrap();
    for _ in 0..30 {
        s.step(DT).unwrap();
    }
    assert_eq!(s.stats().particles, (400.0f64 * 30.0 * DT as f64).floor() as u32);
}

#[test]
fn emitters_give_the_same_water_on_every_run_and_thread_count() {
    let run = |threads: u32| {
        let mut s = sim(threads);
        s.set_rain(Some(rain())).unwrap();
        s.set_spray(Some(spray())).unwrap();
        for _ in 0..60 {
            s.step(DT).unwrap();
        }
        let (x, v) = s.water().unwrap();
        let mut out = vec![0.0f32; s.vertex_count() * s.attributes().stride()];
        s.write_vertices(&mut out).unwrap();
        (x, v, out)
    };
    let one = run(1);
    assert!(!one.0.is_empty());
    for t in [1, 2, 3] {
        let other = run(t);
        assert_eq!(one.0, other.0, "{t} threads: particle positions");
        assert_eq!(one.1, other.1, "{t} threads: particle velocities");
        assert!(one.2.iter().zip(&other.2).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
    // After a reset the clock restarts, and so do the drops.
    let mut s = sim(2);
    s.set_rain(Some(rain())).unwrap();
    for _ in 0..10 {
        s.step(DT).unwrap();
    }
    let first = s.water().unwrap().0;
    s.reset().unwrap();
    for _ in 0..10 {
        s.step(DT).unwrap();
    }
    assert_eq!(first, s.water().unwrap().0, "a replay rains alike");
}

#[test]
fn emitters_never_overfill_the_capacity() {
    let groom = paper_scene(50, 6).unwrap();
    let mut p = SimParams {
        backend: Backend::CPU,
        ..SimParams::paper()
    };
    p.water.capacity = 500;
    p.water.domain_radius = 10.0;
    let mut s = Simulation::new(&groom, p).unwrap();
    s.set_rain(Some(Rain { rate: 1.0e5, ..rain() })).unwrap();
    for _ in 0..20 {
        s.step(DT).unwrap();
        assert!(s.stats().particles <= 500);
    }
    assert_eq!(s.stats().particles, 500, "filled, not overfilled");
}

#[test]
fn bad_emitters_are_refused_by_name_and_change_nothing() {
    let mut s = sim(1);
    s.set_rain(Some(rain())).unwrap();
    let bad_rain = [
        (
            Rain {
                rate: f32::NAN,
                ..rain()
            },
            "rate",
        ),
        (Rain { rate: -1.0, ..rain() }, "rate"),
        (
            Rain {
                size: [-0.1, 0.2],
                ..rain()
            },
            "rain size",
        ),
        (
            Rain {
                center: Vec3::new(f32::INFINITY, 0.0, 0.0),
                ..rain()
            },
            "rain center",
        ),
        (Rain { speed: 1e4, ..rain() }, "speed"),
    ];
    for (r, name) in bad_rain {
        let e = s.set_rain(Some(r)).unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
    let bad_spray = [
        (
            Spray {
                direction: Vec3::ZERO,
                ..spray()
            },
            "direction",
        ),
        (
            Spray {
                half_angle: 4.0,
                ..spray()
            },
            "half_angle",
        ),
        (
            Spray {
                origin: Vec3::new(0.0, f32::NAN, 0.0),
                ..spray()
            },
            "spray origin",
        ),
    ];
    for (sp, name) in bad_spray {
        let e = s.set_spray(Some(sp)).unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
    // The good rain set first still falls; no spray was set.
    s.step(DT).unwrap();
    assert_eq!(s.stats().particles, (250.0f64 * DT as f64).floor() as u32);
}

#[test]
fn the_c_calls_start_and_stop_emitters_and_check_them() {
    use wethair::ffi::*;
    let mut g = std::ptr::null_mut();
    assert_eq!(
        unsafe { wethair_groom_create_paper_scene(100, 6, &mut g) },
        WetHairResult::WETHAIR_OK
    );
    let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
    unsafe { wethair_sim_desc_default(d.as_mut_ptr()) };
    let mut d = unsafe { d.assume_init() };
    d.groom = g;
    d.backend = Backend::CPU as u32;
    let mut s = std::ptr::null_mut();
    assert_eq!(unsafe { wethair_sim_create(&d, &mut s) }, WetHairResult::WETHAIR_OK);
    let r = WetHairRain {
        center: [0.0, 0.0, 0.5],
        size: [0.2, 0.2],
        rate: 120.0,
        speed: 2.0,
        seed: 1,
    };
    let sp = WetHairSpray {
        origin: [0.3, 0.0, 0.2],
        direction: [-1.0, 0.0, 0.0],
        half_angle: 0.2,
        rate: 60.0,
        speed: 2.0,
        seed: 2,
    };
    let bad = WetHairRain { rate: -5.0, ..r };
    let bad_spray = WetHairSpray {
        half_angle: f32::NAN,
        ..sp
    };
    unsafe {
        assert_eq!(
            wethair_sim_set_rain(s, &bad),
            WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_sim_set_spray(s, &bad_spray),
            WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert_eq!(
            wethair_sim_set_rain(std::ptr::null_mut(), &r),
            WetHairResult::WETHAIR_ERROR_NULL_POINTER
        );
        assert_eq!(wethair_sim_set_rain(s, &r), WetHairResult::WETHAIR_OK);
        assert_eq!(wethair_sim_set_spray(s, &sp), WetHairResult::WETHAIR_OK);
        assert_eq!(wethair_sim_step(s, 0.5), WetHairResult::WETHAIR_OK);
        let mut st = std::mem::MaybeUninit::<WetHairStats>::zeroed();
        (*st.as_mut_ptr()).struct_size = std::mem::size_of::<WetHairStats>() as u32;
        assert_eq!(wethair_sim_get_stats(s, st.as_mut_ptr()), WetHairResult::WETHAIR_OK);
        let now = st.assume_init();
        assert_eq!(
            now.particles as u64 + now.particles_removed,
            60 + 30,
            "half a second of both"
        );
        // NULL stops each.
        assert_eq!(wethair_sim_set_rain(s, std::ptr::null()), WetHairResult::WETHAIR_OK);
        assert_eq!(wethair_sim_set_spray(s, std::ptr::null()), WetHairResult::WETHAIR_OK);
        let before = st.assume_init().particles;
        assert_eq!(wethair_sim_step(s, DT), WetHairResult::WETHAIR_OK);
        assert_eq!(wethair_sim_get_stats(s, st.as_mut_ptr()), WetHairResult::WETHAIR_OK);
        assert!(st.assume_init().particles <= before, "no new drops");
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}
