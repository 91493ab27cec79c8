//! Guides and followers with level of detail (issue 17, item 1; `physics/followers.rs`,
//! docs/GUIDES.md): with every strand a guide the output equals the plain simulation's bit for
//! bit; followers' roots stay on a turning head; wet followers clump around their guides; a
//! change of the simulated fraction neither pops nor keeps simulating the guides it drops; the
//! GPU writes what the CPU writes; results repeat on any thread count; bad guide parameters
//! are refused by name.

use crate::common::{backends, serial};
use glam::{Affine3A, Mat4, Quat, Vec3};
use wethair::groom::{load_file_with, paper_scene, Groom, LoadOptions, UpAxis};
use wethair::physics::clumping::mean_nearest_along_strands;
use wethair::scenes::{shower, Lcg};
use wethair::{Backend, Error, GuideChoice, Guides, SimParams, Simulation};

const DT: f32 = 1.0 / 60.0;

/// The paper scene's parameters with `guides`, on `backend`.
fn params(backend: Backend, guides: Guides) -> SimParams {
    SimParams {
        backend,
        guides,
        ..SimParams::paper_scene_with_head()
    }
}

/// Every vertex's floats after `frames` steps with the head turning about z (0.5 rad/s) and
/// swaying along x.
fn run(sim: &mut Simulation, frames: u32) -> Vec<f32> {
    for f in 0..frames {
        sim.set_head_transform(head_at(f + 1)).unwrap();
        sim.step(DT).unwrap();
    }
    vertices(sim)
}

fn head_at(frame: u32) -> Mat4 {
    let t = frame as f32 * DT;
    Mat4::from_rotation_translation(
        Quat::from_rotation_z(0.5 * t),
        Vec3::new(0.05 * (4.0 * t).sin(), 0.0, 0.0),
    )
}

fn vertices(sim: &mut Simulation) -> Vec<f32> {
    let mut v = vec![0.0; sim.vertex_count() * sim.attributes().stride()];
    sim.write_vertices(&mut v).unwrap();
    v
}

/// Positions among `v` (the default attributes: position first, 7 floats).
fn positions(v: &[f32]) -> Vec<Vec3> {
    v.chunks(7).map(|c| Vec3::new(c[0], c[1], c[2])).collect()
}

/// Every strand a guide: the backend holds them in spread order and writes the output through
/// the followers' pass, and the vertices are the plain simulation's, bit for bit (the physics
/// of a dry strand does not depend on where it sits).
#[test]
fn every_strand_a_guide_writes_the_plain_simulations_vertices() {
    let _serial = serial();
    let g = paper_scene(500, 12).unwrap();
    let mut plain = Simulation::new(&g, params(Backend::CPU, Guides::ALL)).unwrap();
    let mut all = Simulation::new(&g, params(Backend::CPU, Guides::every_nth(1))).unwrap();
    assert_eq!(all.guide_counts(), Some((500, 500)));
    let (a, b) = (run(&mut plain, 40), run(&mut all, 40));
    assert_eq!(a.len(), b.len());
    let same = a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
    assert!(same, "every strand a guide differs from the plain simulation");
}

/// A tenth of the strands simulated: the output covers every strand, every follower's root
/// stays on the turning head (pinned roots carried by the head's rotation), and the guides
/// alone are in the backend.
#[test]
fn followers_cover_every_strand_and_keep_their_roots_on_the_head() {
    let _serial = serial();
    let g = paper_scene(2000, 12).unwrap();
    for backend in backends() {
        let mut sim = Simulation::new(&g, params(backend, Guides::every_nth(10))).unwrap();
        assert_eq!(sim.guide_counts(), Some((200, 200)));
        assert_eq!(sim.vertex_count(), g.point_count());
        assert_eq!(sim.positions().len(), 200 * 12, "the backend holds the guides only");
        let x = positions(&run(&mut sim, 60));
        let head = Affine3A::from_mat4(head_at(60));
        let worst = (0..g.strand_count())
            .map(|s| {
                let r = g.strand_range(s).start;
                x[r].distance(head.transform_point3(g.positions()[r]))
            })
            .fold(0.0f32, f32::max);
        eprintln!("{backend:?}: followers' roots at most {worst:e} m off the head");
        assert!(worst < 1e-5, "{backend:?}: a follower's root is {worst} m off the head");
        assert!(x.iter().all(|p| p.is_finite()));
    }
}

/// The paper scene showered: wet followers close on their guides, so the whole output clumps
/// more (the mean nearest other strand along the strands) with `clump` 0.8 than with 0, though
/// only the guides carry water.
#[test]
fn wet_followers_clump_around_their_guides() {
    let _serial = serial();
    let g = paper_scene(2000, 12).unwrap();
    let tips_after = |clump: f32| {
        let guides = Guides {
            clump,
            ..Guides::every_nth(8)
        };
        let mut sim = Simulation::new(&g, params(Backend::CPU, guides)).unwrap();
        let (p, v) = shower(20_000, &mut Lcg(3));
        sim.add_water(&p, &v).unwrap();
        let out = run(&mut sim, 90);
        let first: Vec<u32> = (0..=g.strand_count())
            .map(|s| {
                if s < g.strand_count() {
                    g.strand_range(s).start as u32
                } else {
                    g.point_count() as u32
                }
            })
            .collect();
        mean_nearest_along_strands(&positions(&out), &first)
    };
    let (loose, clumped) = (tips_after(0.0), tips_after(0.8));
    eprintln!(
        "mean nearest other strand along the strands: {:.2} mm without follower clumping, {:.2} mm with",
        loose * 1e3,
        clumped * 1e3
    );
    assert!(
        clumped < 0.8 * loose,
        "wet followers did not clump: {clumped} vs {loose}"
    );
}

/// The largest distance any vertex moves from one frame to the next over `frames` frames,
/// with `at(f)` run before frame `f`.
fn largest_jump(sim: &mut Simulation, frames: u32, first: u32, mut at: impl FnMut(u32, &mut Simulation)) -> f32 {
    let mut last = positions(&vertices(sim));
    let mut worst = 0.0f32;
    for f in first..first + frames {
        at(f, sim);
        sim.set_head_transform(head_at(f + 1)).unwrap();
        sim.step(DT).unwrap();
        let x = positions(&vertices(sim));
        let j = x.iter().zip(&last).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        worst = worst.max(j);
        last = x;
    }
    worst
}

/// Lowering the simulated fraction from half the strands to an eighth and raising it back
/// while the head turns: over the three frames after each change the output moves no more
/// than 1.5 times the most it moved in the ten frames before (the old and new bindings blend
/// over `blend_time`); the same change with no blend jumps at least twice as far; once the
/// blend has settled the dropped guides are no longer simulated (their state stands still).
#[test]
fn a_change_of_the_simulated_fraction_does_not_pop() {
    let _serial = serial();
    let g = paper_scene(2000, 12).unwrap();
    for backend in backends() {
        let jumps = |blend_time: f32| {
            let guides = Guides {
                blend_time,
                ..Guides::every_nth(2)
            };
            let mut sim = Simulation::new(&g, params(backend, guides)).unwrap();
            run(&mut sim, 30);
            let calm = largest_jump(&mut sim, 10, 30, |_, _| {});
            let down = largest_jump(&mut sim, 3, 40, |f, s| {
                if f == 40 {
                    s.set_guide_fraction(0.25).unwrap();
                }
            });
            assert_eq!(sim.guide_counts(), Some((250, 1000)));
            largest_jump(&mut sim, 17, 43, |_, _| {});
            let calm_low = largest_jump(&mut sim, 10, 60, |_, _| {});
            let up = largest_jump(&mut sim, 3, 70, |f, s| {
                if f == 70 {
                    s.set_guide_fraction(1.0).unwrap();
                }
            });
            (calm, down, calm_low, up, sim)
        };
        let (calm, down, calm_low, up, _) = jumps(0.25);
        let (_, down_at_once, _, up_at_once, mut sim) = jumps(0.0);
        eprintln!(
            "{backend:?}: largest frame-to-frame move {:.1} mm before lowering the fraction, {:.1} mm as it lowers ({:.1} mm at once); \
             {:.1} mm before raising it, {:.1} mm as it rises ({:.1} mm at once)",
            calm * 1e3,
            down * 1e3,
            down_at_once * 1e3,
            calm_low * 1e3,
            up * 1e3,
            up_at_once * 1e3,
        );
        assert!(down < 1.5 * calm, "{backend:?}: lowering the fraction jumped {down} m");
        assert!(up < 1.5 * calm_low, "{backend:?}: raising the fraction jumped {up} m");
        assert!(down_at_once > 2.0 * down, "{backend:?}: the blend made no difference");
        // Lowered again at once: guides past the first quarter stand still.
        sim.set_guide_fraction(0.25).unwrap();
        sim.set_head_transform(head_at(200)).unwrap();
        sim.step(DT).unwrap();
        let before = sim.positions();
        sim.set_head_transform(head_at(201)).unwrap();
        sim.step(DT).unwrap();
        let after = sim.positions();
        // (The CPU steps whole blocks of 8 strands: 250 guides run as 256.)
        let kept = 256 * 12;
        assert!(
            before[kept..] == after[kept..],
            "{backend:?}: dropped guides still move"
        );
        assert!(
            before[..250 * 12] != after[..250 * 12],
            "{backend:?}: kept guides stand still"
        );
    }
}

/// The GPU writes the followers as the CPU does: a third of the strands simulated, three
/// guides per follower, the head turning; after 20 frames no vertex is farther from the CPU's
/// than the guides' own distance turned through the followers' offsets (8 times it).
#[test]
fn gpu_followers_equal_cpu_followers() {
    let _serial = serial();
    if !backends().contains(&Backend::GPU) {
        return;
    }
    let g = paper_scene(1200, 12).unwrap();
    let mut cpu = Simulation::new(&g, params(Backend::CPU, Guides::every_nth(3))).unwrap();
    let mut gpu = Simulation::new(&g, params(Backend::GPU, Guides::every_nth(3))).unwrap();
    let (a, b) = (run(&mut cpu, 20), run(&mut gpu, 20));
    let guides = cpu
        .positions()
        .iter()
        .zip(&gpu.positions())
        .map(|(x, y)| x.distance(*y))
        .fold(0.0f32, f32::max);
    let (pa, pb) = (positions(&a), positions(&b));
    let worst = pa.iter().zip(&pb).map(|(x, y)| x.distance(*y)).fold(0.0f32, f32::max);
    let other = a
        .chunks(7)
        .zip(b.chunks(7))
        .flat_map(|(x, y)| x[3..].iter().zip(&y[3..]).map(|(p, q)| (p - q).abs()))
        .fold(0.0f32, f32::max);
    eprintln!("GPU vs CPU: guides {guides:e} m apart, every vertex {worst:e} m, tangents and wetness {other:e}");
    // The followers add no difference of their own beyond the guides': a guide segment's
    // direction differs by the points' distance over its length (5 mm here), which turns an
    // offset of up to 3 cm by that angle, so the followers may differ some times as much as
    // the guides (measured 2026-11-25: guides 0.85 µm, vertices 1.5 µm).
    assert!(
        worst <= 8.0 * guides + 1e-6,
        "GPU followers {worst} m from the CPU's; guides {guides} m"
    );
    assert!(guides < 2e-3, "GPU guides {guides} m from the CPU's");
}

/// The ponytail (517 strands, metres) with 64 guides spread over its scalp, and with 64 chosen
/// by clustering its roots: the real groom's followers stay finite and hang with their guides,
/// and the result repeats bit for bit on 1 and 4 threads.
#[test]
fn a_real_groom_with_spread_or_clustered_guides_is_deterministic_across_threads() {
    let _serial = serial();
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ponytail_back.tfx"));
    let opt = LoadOptions {
        scale: 0.01,
        up_axis: UpAxis::Y_TO_Z,
        ..Default::default()
    };
    let groom: Groom = load_file_with(path, &opt).unwrap();
    for choice in [GuideChoice::Spread(64), GuideChoice::Cluster(64)] {
        let out = |threads: u32| {
            let p = SimParams {
                threads,
                backend: Backend::CPU,
                guides: Guides {
                    choice: choice.clone(),
                    ..Guides::ALL
                },
                ..SimParams::default()
            };
            let mut sim = Simulation::new(&groom, p).unwrap();
            assert_eq!(sim.guide_counts(), Some((64, 64)), "{choice:?}");
            run(&mut sim, 30)
        };
        let (one, four) = (out(1), out(4));
        assert!(one.iter().all(|f| f.is_finite()), "{choice:?}");
        let same = one.iter().zip(&four).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same, "{choice:?}: 1 and 4 threads differ");
    }
}

/// Bad guide parameters are refused by name; a fraction needs guides and a value in (0, 1].
#[test]
fn bad_guides_are_refused() {
    let g = paper_scene(100, 6).unwrap();
    let bad = |guides: Guides, what: &str| {
        let e = Simulation::new(&g, params(Backend::CPU, guides)).unwrap_err();
        assert!(e.to_string().contains(what), "{what}: {e}");
    };
    bad(
        Guides {
            per_follower: 2,
            ..Guides::every_nth(2)
        },
        "per_follower",
    );
    bad(Guides::every_nth(0), "n >= 1");
    bad(
        Guides {
            choice: GuideChoice::Spread(0),
            ..Guides::ALL
        },
        "at least one",
    );
    bad(
        Guides {
            choice: GuideChoice::Cluster(0),
            ..Guides::ALL
        },
        "at least one",
    );
    bad(
        Guides {
            choice: GuideChoice::Given(vec![1, 5, 1]),
            ..Guides::ALL
        },
        "given twice",
    );
    bad(
        Guides {
            choice: GuideChoice::Given(vec![100]),
            ..Guides::ALL
        },
        "past the groom",
    );
    bad(
        Guides {
            choice: GuideChoice::Given(vec![]),
            ..Guides::ALL
        },
        "empty",
    );
    bad(
        Guides {
            clump: 1.5,
            ..Guides::every_nth(2)
        },
        "guides.clump",
    );
    bad(
        Guides {
            clump: f32::NAN,
            ..Guides::every_nth(2)
        },
        "guides.clump",
    );
    bad(
        Guides {
            fraction: 0.0,
            ..Guides::every_nth(2)
        },
        "guides.fraction",
    );
    bad(
        Guides {
            blend_time: -1.0,
            ..Guides::every_nth(2)
        },
        "guides.blend_time",
    );
    let mut plain = Simulation::new(&g, params(Backend::CPU, Guides::ALL)).unwrap();
    assert!(matches!(plain.set_guide_fraction(0.5), Err(Error::Unsupported(_))));
    let mut sim = Simulation::new(&g, params(Backend::CPU, Guides::every_nth(2))).unwrap();
    for f in [0.0, -0.5, 1.5, f32::NAN, f32::INFINITY] {
        assert!(sim.set_guide_fraction(f).is_err(), "fraction {f} accepted");
    }
    assert_eq!(sim.guide_counts(), Some((50, 50)));
}

/// Fixed steps with interpolated output: with every strand a guide, the followers' pass writes
/// the blend between the last two steps exactly as the plain output does, on each backend.
#[test]
fn followers_show_the_fixed_steps_blend() {
    let _serial = serial();
    let g = paper_scene(300, 10).unwrap();
    for backend in backends() {
        let out = |guides: Guides| {
            let p = SimParams {
                fixed_step: wethair::FixedStep::every(1.0 / 120.0),
                ..params(backend, guides)
            };
            let mut sim = Simulation::new(&g, p).unwrap();
            let mut frames = Vec::new();
            for f in 0..20 {
                sim.set_head_transform(head_at(f + 1)).unwrap();
                sim.advance(1.0 / 144.0).unwrap();
                frames.push(vertices(&mut sim));
            }
            frames
        };
        let (plain, all) = (out(Guides::ALL), out(Guides::every_nth(1)));
        for (f, (a, b)) in plain.iter().zip(&all).enumerate() {
            let worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
            assert!(
                worst == 0.0,
                "{backend:?} frame {f}: the followers' blend is {worst} from the plain one"
            );
        }
    }
}

/// Guides through the C ABI: a given list, the vertex layout covering every strand, the
/// fraction changed at run time, and bad input refused with a message and nothing changed; a
/// 0.4.0 host's 296-byte desc has no guides.
#[test]
fn guides_through_c() {
    use std::ptr::null_mut;
    use wethair::ffi::*;
    use WetHairResult::*;
    let mut g = null_mut();
    assert_eq!(unsafe { wethair_groom_create_paper_scene(400, 8, &mut g) }, WETHAIR_OK);
    let desc = |size: u32| {
        let mut d = std::mem::MaybeUninit::<WetHairSimDesc>::zeroed();
        assert_eq!(unsafe { wethair_sim_desc_init(d.as_mut_ptr(), size) }, WETHAIR_OK);
        let mut d = unsafe { d.assume_init() };
        d.groom = g;
        d.backend = Backend::CPU as u32;
        d
    };
    let full = std::mem::size_of::<WetHairSimDesc>() as u32;
    let d0 = desc(full);
    assert_eq!(
        d0.guides.choice,
        WetHairGuideChoice::WETHAIR_GUIDES_ALL as u32,
        "off by default"
    );
    assert_eq!((d0.guides.per_follower, d0.guides.fraction), (3, 1.0));
    let list: Vec<u32> = (0..400).step_by(5).collect();
    let create = |d: &WetHairSimDesc| {
        let mut s = null_mut();
        let r = unsafe { wethair_sim_create(d, &mut s) };
        (r, s)
    };
    let mut d = desc(full);
    d.guides.choice = WetHairGuideChoice::WETHAIR_GUIDES_GIVEN as u32;
    d.guides.count = list.len() as u32;
    d.guides.strands = list.as_ptr();
    let (r, s) = create(&d);
    assert_eq!(r, WETHAIR_OK, "{}", crate::common::last_error());
    let mut layout = std::mem::MaybeUninit::<WetHairVertexLayout>::zeroed();
    unsafe { (*layout.as_mut_ptr()).struct_size = std::mem::size_of::<WetHairVertexLayout>() as u32 };
    assert_eq!(
        unsafe { wethair_sim_get_vertex_layout(s, layout.as_mut_ptr()) },
        WETHAIR_OK
    );
    let layout = unsafe { layout.assume_init() };
    assert_eq!((layout.vertex_count, layout.strand_count), (400 * 8, 400));
    assert_eq!(unsafe { wethair_sim_step(s, DT) }, WETHAIR_OK);
    assert_eq!(unsafe { wethair_sim_set_guide_fraction(s, 0.5) }, WETHAIR_OK);
    for bad in [0.0, 1.5, f32::NAN] {
        assert_eq!(
            unsafe { wethair_sim_set_guide_fraction(s, bad) },
            WETHAIR_ERROR_INVALID_ARGUMENT
        );
        assert!(crate::common::last_error().contains("guide fraction"));
    }
    assert_eq!(
        unsafe { wethair_sim_set_guide_fraction(null_mut(), 0.5) },
        WETHAIR_ERROR_NULL_POINTER
    );
    assert_eq!(unsafe { wethair_sim_step(s, DT) }, WETHAIR_OK);
    unsafe { wethair_sim_destroy(s) };
    // Clustered guides: 40 of the 400 strands.
    let mut c = desc(full);
    c.guides.choice = WetHairGuideChoice::WETHAIR_GUIDES_CLUSTER as u32;
    c.guides.count = 40;
    let (r, cs) = create(&c);
    assert_eq!(r, WETHAIR_OK, "{}", crate::common::last_error());
    assert_eq!(unsafe { wethair_sim_step(cs, DT) }, WETHAIR_OK);
    unsafe { wethair_sim_destroy(cs) };
    // The same guides on skinned roots: one frame per strand of the groom (followers
    // included; the guides' count is refused), every strand's root on its own frame.
    let mut k = c;
    k.skinned_roots = 1;
    let (r, ks) = create(&k);
    assert_eq!(r, WETHAIR_OK, "{}", crate::common::last_error());
    let shift = Vec3::new(0.01, -0.02, 0.03);
    let paper = paper_scene(400, 8).unwrap();
    let (pos, rot): (Vec<f32>, Vec<f32>) = (
        (0..400)
            .flat_map(|s| (paper.positions()[s * 8] + shift).to_array())
            .collect(),
        (0..400).flat_map(|_| [0.0, 0.0, 0.0, 1.0]).collect(),
    );
    let set = |n: u32| unsafe { wethair_sim_set_root_frames(ks, pos.as_ptr(), rot.as_ptr(), n) };
    assert_eq!(set(40), WETHAIR_ERROR_INVALID_ARGUMENT);
    assert!(
        crate::common::last_error().contains("400 strands"),
        "{}",
        crate::common::last_error()
    );
    assert_eq!(set(400), WETHAIR_OK, "{}", crate::common::last_error());
    assert_eq!(
        unsafe { wethair_sim_step(ks, DT) },
        WETHAIR_OK,
        "{}",
        crate::common::last_error()
    );
    let mut v = vec![0.0f32; 400 * 8 * 7];
    let mut written = 0;
    let r = unsafe { wethair_sim_get_vertex_buffer(ks, v.as_mut_ptr(), v.len(), &mut written) };
    assert_eq!((r, written), (WETHAIR_OK, v.len()));
    let off = (0..400)
        .map(|s| Vec3::from_slice(&v[s * 8 * 7..]).distance(paper.positions()[s * 8] + shift))
        .fold(0.0, f32::max);
    assert!(off < 1e-6, "a root is {off} m from its frame");
    unsafe { wethair_sim_destroy(ks) };
    // A NULL list, a bad choice, a repeated strand: refused by name, no simulation made.
    let mut bad = d;
    bad.guides.strands = std::ptr::null();
    assert_eq!(create(&bad), (WETHAIR_ERROR_NULL_POINTER, null_mut()));
    assert!(crate::common::last_error().contains("guides.strands"));
    let mut bad = d;
    bad.guides.choice = 9;
    assert_eq!(create(&bad), (WETHAIR_ERROR_INVALID_ARGUMENT, null_mut()));
    assert!(crate::common::last_error().contains("guides.choice"));
    let twice = [3u32, 3];
    let mut bad = d;
    bad.guides.strands = twice.as_ptr();
    bad.guides.count = 2;
    assert_eq!(create(&bad), (WETHAIR_ERROR_INVALID_ARGUMENT, null_mut()));
    assert!(crate::common::last_error().contains("given twice"));
    // A 0.4.0 host: its desc ends before the guides, which take their default (off).
    let mut old = d;
    old.struct_size = 296;
    let (r, s) = create(&old);
    assert_eq!(r, WETHAIR_OK);
    assert_eq!(
        unsafe { wethair_sim_set_guide_fraction(s, 0.5) },
        WETHAIR_ERROR_UNSUPPORTED
    );
    unsafe {
        wethair_sim_destroy(s);
        wethair_groom_destroy(g);
    }
}

/// The live error estimate with guides samples the simulated guides as a plain simulation of
/// the same strands does: the same estimate, bit for bit (the shadow has no guides of its own).
#[test]
fn the_error_estimate_samples_the_guides() {
    let _serial = serial();
    let g = paper_scene(400, 8).unwrap();
    let p = |guides: Guides| SimParams {
        threads: 1,
        error_estimate_stride: 3,
        ..params(Backend::CPU, guides)
    };
    let mut guided = Simulation::new(&g, p(Guides::every_nth(4))).unwrap();
    let order = guided.guide_strands().unwrap().to_vec();
    let mut plain = Simulation::new(&g.subset(&order), p(Guides::ALL)).unwrap();
    for f in 0..10 {
        for s in [&mut guided, &mut plain] {
            s.set_head_transform(head_at(f + 1)).unwrap();
            s.step(DT).unwrap();
        }
    }
    let (a, b) = (guided.stats().error_estimate, plain.stats().error_estimate);
    assert!(a.is_some(), "no estimate with guides");
    assert_eq!(
        format!("{a:?}"),
        format!("{b:?}"),
        "the guides' estimate differs from the plain one"
    );
}
