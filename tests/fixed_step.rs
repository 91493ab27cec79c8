//! Fixed-step updates (issue 17, item 5; `sim/fixed.rs`): hosts at 30, 60 and 144 Hz end
//! bit-identical after the same simulated time, on both backends and with rain and gusting
//! wind (which follow the simulated clock); the vertices lie between the last two steps by the
//! time left over; the head moves across a frame's steps and lands on the host's transform; a
//! hitch is capped and reported; nothing is kept when interpolation is off; bad frame times
//! and settings are refused and change nothing.

use crate::common::{backends, serial};
use glam::{Mat4, Vec3};
use wethair::groom::{paper_scene, Groom};
use wethair::{Backend, Error, FixedStep, HeldWater, SimParams, Simulation, VertexAttributes, Wind};

/// The fixed step of these tests, s.
const H: f32 = 1.0 / 120.0;

/// 200 strands of the paper scene under rain and gusting wind, with held water (absorb,
/// flow, drip, dry: every pass the GPU runs), in fixed steps of `H`.
fn wet(backend: Backend, fixed: FixedStep) -> Simulation {
    let groom = paper_scene(200, 6).unwrap();
    let mut p = SimParams {
        backend,
        threads: 2,
        fixed_step: fixed,
        held_water: HeldWater {
            bridge_tension: 0.0,
            ..HeldWater::ON
        },
        wind: Wind {
            velocity: Vec3::new(1.5, 0.0, 0.0),
            gust: 0.5,
            seed: 3,
        },
        ..SimParams::paper()
    };
    p.water.domain_radius = 10.0;
    let mut s = Simulation::new(&groom, p).unwrap();
    s.set_rain(Some(wethair::Rain {
        center: Vec3::new(0.0, 0.0, 0.6),
        size: [0.3, 0.2],
        rate: 400.0,
        speed: 3.0,
        seed: 5,
    }))
    .unwrap();
    s
}

fn bits(v: &[Vec3]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

#[test]
fn hosts_at_30_60_and_144_hz_end_bit_identical_on_each_backend() {
    let _serial = serial();
    for backend in backends() {
        let mut ends = Vec::new();
        for hz in [30u32, 60, 144] {
            let mut s = wet(backend, FixedStep::every(H));
            let mut steps = 0;
            for _ in 0..hz {
                steps += s.advance(1.0 / hz as f32).unwrap().steps;
            }
            assert_eq!(steps, 120, "{backend:?} at {hz} Hz");
            assert_eq!(s.stats().steps, 120);
            let st = s.stats();
            assert!(
                st.particles > 100,
                "{backend:?}: rain fell ({} particles)",
                st.particles
            );
            ends.push((hz, bits(&s.positions()), bits(&s.water_positions().unwrap())));
        }
        // The host stepping 120 times by H itself computes the same.
        let mut direct = wet(backend, FixedStep::OFF);
        for _ in 0..120 {
            direct.step(H).unwrap();
        }
        ends.push((0, bits(&direct.positions()), bits(&direct.water_positions().unwrap())));
        // The device keeps particles in the order its atomics gave out slots, which on an H100
        // changes with how steps are batched (the set does not); reads hand them over sorted
        // by their bits.
        assert!(
            ends.iter().all(|e| e.2.windows(2).all(|w| w[0] <= w[1])) || backend == Backend::CPU,
            "GPU particles read in the device's order"
        );
        for e in &ends[1..] {
            assert!(e.1 == ends[0].1, "{backend:?}: hair at {} Hz differs from 30 Hz", e.0);
            assert!(e.2 == ends[0].2, "{backend:?}: water at {} Hz differs from 30 Hz", e.0);
        }
    }
}

/// The positions of vertices `v` (stride `stride`, positions first).
fn vertex_positions(v: &[f32], stride: usize) -> Vec<Vec3> {
    v.chunks(stride).map(Vec3::from_slice).collect()
}

fn vertices(s: &mut Simulation) -> Vec<f32> {
    let mut v = vec![0.0; s.vertex_count() * s.attributes().stride()];
    s.write_vertices(&mut v).unwrap();
    v
}

/// A swinging 12-strand slice (dry: the state alone moves), positions and tangents out.
fn swinging(backend: Backend, fixed: FixedStep) -> Simulation {
    let sc = wethair::scenes::paper_slice(12, 0, 1.0);
    let p = SimParams {
        backend,
        fixed_step: fixed,
        attributes: VertexAttributes(VertexAttributes::POSITION | VertexAttributes::TANGENT),
        ..sc.params.clone()
    };
    Simulation::new(&sc.groom, p).unwrap()
}

#[test]
fn the_vertices_lie_between_the_last_two_steps_by_the_time_left_over() {
    let _serial = serial();
    for backend in backends() {
        // Where the state is after 1 and 2 steps of H, stepped by the host.
        let mut r = swinging(backend, FixedStep::OFF);
        r.step(H).unwrap();
        let p1 = r.positions();
        r.step(H).unwrap();
        let p2 = r.positions();
        // A 50 Hz host: the first frame takes two steps and leaves 0.4 of a step over.
        let mut s = swinging(backend, FixedStep::every(H));
        let a = s.advance(1.0 / 50.0).unwrap();
        assert_eq!(a.steps, 2);
        assert!((a.blend - 0.4).abs() < 1e-4, "{a:?}");
        assert!(
            bits(&s.positions()) == bits(&p2),
            "{backend:?}: the state is the second step's"
        );
        let stride = s.attributes().stride();
        let check = |v: &[f32], blend: f32, what: &str| {
            let want: Vec<Vec3> = p1.iter().zip(&p2).map(|(p, x)| *p + blend * (*x - *p)).collect();
            let got = vertex_positions(v, stride);
            // The CPU's blend is this very expression; the GPU's may fuse it.
            let tol = if backend == Backend::CPU { 0.0 } else { 1e-6 };
            let gap = got
                .iter()
                .zip(&want)
                .map(|(g, w)| (*g - *w).abs().max_element())
                .fold(0.0, f32::max);
            assert!(gap <= tol, "{backend:?} {what}: blended positions {gap:e} m off");
            // Tangents follow the blended positions (central differences within a strand).
            for i in [1usize, 2, 3, 4] {
                let t = Vec3::from_slice(&v[i * stride + 3..]);
                let d = (want[i + 1] - want[i - 1]).normalize();
                assert!(
                    (t - d).length() < 1e-5,
                    "{backend:?} {what}: tangent {i} {t} against {d}"
                );
            }
            let moved = got.iter().zip(&p2).map(|(g, x)| (*g - *x).length()).fold(0.0, f32::max);
            assert!(
                blend == 1.0 || moved > 1e-7,
                "{backend:?} {what}: the blend shows the last step"
            );
        };
        check(&vertices(&mut s), a.blend, "after the first frame");
        // A short frame takes no step: the same two states, blended further.
        let b = s.advance(0.002).unwrap();
        assert_eq!(b.steps, 0);
        assert!((b.blend - 0.64).abs() < 1e-4, "{b:?}");
        assert!(bits(&s.positions()) == bits(&p2));
        check(&vertices(&mut s), b.blend, "after a frame without a step");
        // A step of the host's own shows the state it reached.
        s.step(H).unwrap();
        let v = vertices(&mut s);
        assert!(
            bits(&vertex_positions(&v, stride)) == bits(&s.positions()),
            "{backend:?}: a plain step's vertices are its state"
        );
        // Interpolation off: the vertices are the last step's state, and nothing is kept.
        let mut off = swinging(
            backend,
            FixedStep {
                interpolate: false,
                ..FixedStep::every(H)
            },
        );
        let a = off.advance(1.0 / 50.0).unwrap();
        assert_eq!((a.steps, a.blend), (2, 1.0));
        let v = vertices(&mut off);
        assert!(bits(&vertex_positions(&v, stride)) == bits(&p2), "{backend:?}");
        let kept = |s: &Simulation| s.buffers().iter().any(|b| b.0 == "output_from");
        assert!(!kept(&off), "{backend:?}: no copy without interpolation");
        assert!(kept(&s), "{backend:?}: the interpolating simulation keeps one copy");
        assert!(
            !kept(&swinging(backend, FixedStep::every(H))),
            "nothing kept before a step"
        );
    }
}

#[test]
fn the_head_moves_across_a_frames_steps_and_lands_on_the_hosts_transform() {
    let _serial = serial();
    for backend in backends() {
        let mut s = swinging(backend, FixedStep::every(H));
        let groom: Groom = wethair::scenes::paper_slice(12, 0, 1.0).groom;
        let root = groom.positions()[0];
        // A 30 Hz frame is four whole steps: the root ends exactly where the host put the head.
        let m = Mat4::from_translation(Vec3::new(0.01, 0.0, 0.0));
        s.set_head_transform(m).unwrap();
        assert_eq!(s.advance(1.0 / 30.0).unwrap().steps, 4);
        let at = s.positions()[0];
        assert!(
            (at - m.transform_point3(root)).length() < 1e-6,
            "{backend:?}: root at {at}"
        );
        // A 50 Hz frame is two steps of 2.4 owed: the root goes 2/2.4 of the way.
        let m2 = Mat4::from_translation(Vec3::new(0.02, 0.0, 0.0));
        s.set_head_transform(m2).unwrap();
        let a = s.advance(1.0 / 50.0).unwrap();
        assert_eq!(a.steps, 2);
        let want = root + Vec3::new(0.01 + 0.01 * (2.0 / 2.4), 0.0, 0.0);
        let at = s.positions()[0];
        assert!((at - want).length() < 1e-6, "{backend:?}: root at {at}, want {want}");
        // The next frame's first step starts from there; after five 50 Hz frames (12 steps)
        // nothing is owed and the root is on the head.
        for _ in 0..3 {
            s.advance(1.0 / 50.0).unwrap();
        }
        let owed = s.advance(1.0 / 50.0).unwrap();
        assert!(owed.blend < 1e-3, "whole steps again: {owed:?}");
        let at = s.positions()[0];
        assert!(
            (at - m2.transform_point3(root)).length() < 1e-6,
            "{backend:?}: root at {at}"
        );
        // Reset forgets what was owed: a 50 Hz frame takes two steps again.
        s.advance(0.005).unwrap();
        s.reset().unwrap();
        assert_eq!(s.advance(1.0 / 50.0).unwrap().steps, 2);
    }
}

#[test]
fn a_hitch_is_capped_and_reported() {
    let mut s = swinging(
        Backend::CPU,
        FixedStep {
            max_frame: 0.1,
            ..FixedStep::every(H)
        },
    );
    let a = s.advance(0.9).unwrap();
    assert_eq!(a.steps, 12);
    assert!((a.dropped - 0.8).abs() < 1e-6, "{a:?}");
    assert!(s.positions().iter().all(|p| p.is_finite()));
    // Without fixed steps `advance` is `step`, and a frame past MAX_DT is refused.
    let mut plain = swinging(Backend::CPU, FixedStep::OFF);
    assert_eq!(plain.advance(1.0 / 60.0).unwrap().steps, 1);
    assert!(matches!(plain.advance(2.0), Err(Error::InvalidArgument(_))));
}

#[test]
fn bad_frame_times_and_settings_are_refused_and_change_nothing() {
    let mut s = swinging(Backend::CPU, FixedStep::every(H));
    s.advance(0.02).unwrap();
    let before = bits(&s.positions());
    for bad in [f32::NAN, f32::INFINITY, -0.01, f32::NEG_INFINITY] {
        match s.advance(bad) {
            Err(Error::InvalidArgument(m)) => assert!(m.contains("frame time"), "{m}"),
            other => panic!("advance({bad}) gave {other:?}"),
        }
    }
    assert!(bits(&s.positions()) == before);
    assert_eq!(s.advance(0.0).unwrap().steps, 0, "a zero frame is allowed");
    let sc = wethair::scenes::paper_slice(4, 0, 1.0);
    for (fixed, what) in [
        (FixedStep::every(f32::NAN), "fixed_step"),
        (FixedStep::every(-0.01), "fixed_step"),
        (FixedStep::every(2.0), "fixed_step"),
        (
            FixedStep {
                max_frame: 0.001,
                ..FixedStep::every(H)
            },
            "max_frame_time",
        ),
        (
            FixedStep {
                max_frame: f32::INFINITY,
                ..FixedStep::every(H)
            },
            "max_frame_time",
        ),
        (
            FixedStep {
                max_frame: 1.0,
                ..FixedStep::every(1e-4)
            },
            "steps per advance",
        ),
    ] {
        let p = SimParams {
            fixed_step: fixed,
            ..sc.params.clone()
        };
        match Simulation::new(&sc.groom, p) {
            Err(Error::InvalidArgument(m)) => assert!(m.contains(what), "{m}"),
            other => panic!("{fixed:?}: {other:?}"),
        }
    }
}

mod c_abi {
    //! `wethair_sim_advance` and the desc's fixed-step fields through the C ABI.

    use std::ptr::null_mut;
    use wethair::ffi::*;
    use WetHairResult::*;

    use crate::common::last_error;

    /// A CPU simulation of 16 paper strands from `d` (the current defaults with `edit`), or
    /// the create's result.
    fn create(edit: impl FnOnce(&mut WetHairSimDesc)) -> Result<*mut WetHairSim, WetHairResult> {
        let mut g = null_mut();
        assert_eq!(unsafe { wethair_groom_create_paper_scene(16, 6, &mut g) }, WETHAIR_OK);
        let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
        let size = std::mem::size_of::<WetHairSimDesc>() as u32;
        assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
        let mut d = unsafe { d.assume_init() };
        assert_eq!(
            (d.fixed_step, d.max_frame_time, d.interpolate),
            (0.0, 0.25, 1),
            "defaults"
        );
        d.groom = g;
        d.backend = wethair::Backend::CPU as u32;
        edit(&mut d);
        let mut s = null_mut();
        let r = unsafe { wethair_sim_create(&d, &mut s) };
        unsafe { wethair_groom_destroy(g) };
        if r == WETHAIR_OK {
            Ok(s)
        } else {
            assert!(s.is_null());
            Err(r)
        }
    }

    fn out() -> WetHairAdvance {
        WetHairAdvance {
            struct_size: std::mem::size_of::<WetHairAdvance>() as u32,
            steps: 777,
            blend: 7.0,
            dropped_time: 7.0,
        }
    }

    fn steps(s: *const WetHairSim) -> u64 {
        let mut st = std::mem::MaybeUninit::<WetHairStats>::zeroed();
        unsafe { (*st.as_mut_ptr()).struct_size = std::mem::size_of::<WetHairStats>() as u32 };
        assert_eq!(unsafe { wethair_sim_get_stats(s, st.as_mut_ptr()) }, WETHAIR_OK);
        unsafe { st.assume_init() }.steps
    }

    #[test]
    fn fixed_steps_reach_c_hosts() {
        let s = create(|d| d.fixed_step = 1.0 / 120.0).unwrap();
        let mut o = out();
        assert_eq!(unsafe { wethair_sim_advance(s, 1.0 / 50.0, &mut o) }, WETHAIR_OK);
        assert_eq!(o.steps, 2);
        assert!((o.blend - 0.4).abs() < 1e-4 && o.dropped_time == 0.0, "{o:?}");
        // NULL out is allowed; a bad frame time or out size is refused and writes nothing.
        assert_eq!(
            unsafe { wethair_sim_advance(s, 1.0 / 50.0, std::ptr::null_mut()) },
            WETHAIR_OK
        );
        assert_eq!(steps(s), 4);
        for bad in [f32::NAN, -1.0, f32::INFINITY] {
            let mut o = out();
            assert_eq!(
                unsafe { wethair_sim_advance(s, bad, &mut o) },
                WETHAIR_ERROR_INVALID_ARGUMENT
            );
            assert!(last_error().contains("frame time"), "{}", last_error());
            assert_eq!((o.steps, o.blend), (777, 7.0), "nothing written");
        }
        let mut o = WetHairAdvance {
            struct_size: 8,
            ..out()
        };
        assert_eq!(
            unsafe { wethair_sim_advance(s, 0.01, &mut o) },
            WETHAIR_ERROR_STRUCT_SIZE
        );
        assert_eq!(o.steps, 777);
        assert_eq!(steps(s), 4, "no step on a refused call");
        assert_eq!(
            unsafe { wethair_sim_advance(null_mut(), 0.01, null_mut()) },
            WETHAIR_ERROR_NULL_POINTER
        );
        unsafe { wethair_sim_destroy(s) };
        // Bad settings are refused by name at create.
        for (edit, name) in [
            ((f32::NAN, 0.25, 1), "fixed_step"),
            ((-0.01, 0.25, 1), "fixed_step"),
            ((0.01, 0.001, 1), "max_frame_time"),
            ((0.01, 0.25, 2), "interpolate"),
        ] {
            let r = create(|d| (d.fixed_step, d.max_frame_time, d.interpolate) = edit);
            assert_eq!(r.err(), Some(WETHAIR_ERROR_INVALID_ARGUMENT), "{edit:?}");
            assert!(last_error().contains(name), "{}", last_error());
        }
        // A 0.3.0 host's desc (232 bytes) has no fixed step: advance is a step of the frame.
        let s = create(|d| {
            d.struct_size = 232;
            d.fixed_step = 0.01; // past the host's size: not read
        })
        .unwrap();
        let mut o = out();
        assert_eq!(unsafe { wethair_sim_advance(s, 1.0 / 50.0, &mut o) }, WETHAIR_OK);
        assert_eq!((o.steps, o.blend), (1, 1.0));
        unsafe { wethair_sim_destroy(s) };
    }
}
