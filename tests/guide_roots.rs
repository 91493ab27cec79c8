//! Guides and followers on skinned roots (issue 17, items 1 and 2 together;
//! `physics/follow_roots.rs`, docs/GUIDES.md): on a stretching, waving sheet every strand's
//! root points (guides and followers alike) land on their own frames within a micrometre on
//! both backends, and the followers stay near every strand simulated; roots that follow the head give what the head
//! gives; a jump past the teleport distance carries the guides at rest and the followers with
//! them; a guide that starts to be simulated starts where the output showed it; the fixed
//! steps' blend shows the roots between the last two steps; results repeat on any thread
//! count, and the GPU writes what the CPU writes.

use crate::common::{backends, frames_moved, frames_on_head, serial};
use glam::{Mat4, Quat, Vec3};
use wethair::groom::Groom;
use wethair::physics::roots::RootFrame;
use wethair::{Backend, FixedStep, Guides, SimParams, Simulation};

/// Points per strand; the first two are pinned (as TressFX pins them).
const POINTS: usize = 12;
/// Strands per side of the sheet.
const SIDE: usize = 16;
const DT: f32 = 1.0 / 60.0;

/// A 16 × 16 sheet of strands 1 cm apart in the z = 0 plane, each hanging 11 cm straight down
/// in 1 cm segments, the first two points pinned.
fn sheet() -> Groom {
    let mut pos = Vec::new();
    let mut pinned = Vec::new();
    for i in 0..SIDE {
        for j in 0..SIDE {
            let r = Vec3::new(i as f32 * 0.01 - 0.075, j as f32 * 0.01 - 0.075, 0.0);
            for k in 0..POINTS {
                pos.push(r - Vec3::Z * (0.01 * k as f32));
                pinned.push(k < 2);
            }
        }
    }
    Groom::new(pos, &[POINTS as u32; SIDE * SIDE], Some(pinned), None, 1e-6).unwrap()
}

fn params(backend: Backend, guides: Guides) -> SimParams {
    SimParams {
        backend,
        threads: 2,
        guides,
        skinned_roots: true,
        ..SimParams::default()
    }
}

/// A quarter of the strands simulated, each follower from three guides.
fn quarter() -> Guides {
    Guides::every_nth(4)
}

/// The sheet's frames at time `t`: the skin stretches along x by up to 30% (a talking jaw),
/// a wave runs along it in z with each root turned by its slope, and the sheet rocks about x.
fn skin(g: &Groom, t: f32) -> Vec<RootFrame> {
    let stretch = 1.0 + 0.3 * (3.0 * t).sin();
    (0..g.strand_count())
        .map(|s| {
            let r = g.positions()[g.strand_range(s).start];
            let phase = 30.0 * r.x - 6.0 * t;
            let slope = 0.02 * 30.0 * phase.cos();
            RootFrame {
                position: Vec3::new(r.x * stretch, r.y, 0.02 * phase.sin()),
                rotation: Quat::from_rotation_x(0.3 * (2.0 * t).sin()) * Quat::from_rotation_y(-slope.atan()),
            }
        })
        .collect()
}

fn positions(sim: &mut Simulation) -> Vec<Vec3> {
    let mut v = vec![0.0; sim.vertex_count() * sim.attributes().stride()];
    sim.write_vertices(&mut v).unwrap();
    v.chunks(sim.attributes().stride())
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

/// The farthest an output root point is from where its strand's frame puts it, m.
fn root_error(x: &[Vec3], g: &Groom, frames: &[RootFrame]) -> f32 {
    let mut worst = 0.0f32;
    for (s, f) in frames.iter().enumerate() {
        let r = g.strand_range(s);
        let rest = &g.positions()[r.clone()];
        for (p, q) in x[r].iter().zip(rest).take(2) {
            worst = worst.max((*p - f.place(*q - rest[0])).length());
        }
    }
    worst
}

/// On a stretching, waving, rocking skin with a quarter of the strands simulated, every root
/// point of the output (followers' too) is on its own frame within a micrometre, each step
/// and each backend, and the followers stay near where every strand simulated puts them (mean
/// under 1.2 mm over 90 frames: without the shift onto their own roots it was 1.1 mm and the
/// roots were off; with a constant shift 1.6 mm); the GPU writes what the CPU writes.
#[test]
fn every_strands_root_points_follow_a_stretching_skin() {
    let _serial = serial();
    let g = sheet();
    let mut ends = Vec::new();
    for backend in backends() {
        let mut sims = [quarter(), Guides::every_nth(1)].map(|gd| Simulation::new(&g, params(backend, gd)).unwrap());
        assert_eq!(sims[0].guide_counts(), Some((64, 64)));
        let (mut worst, mut lod, mut lod_max, mut n) = (0.0f32, 0.0f64, 0.0f32, 0);
        let mut x = Vec::new();
        for f in 1..=90 {
            let frames = skin(&g, f as f32 * DT);
            for sim in &mut sims {
                sim.set_root_frames(&frames).unwrap();
                sim.step(DT).unwrap();
            }
            x = positions(&mut sims[0]);
            worst = worst.max(root_error(&x, &g, &frames));
            for (p, q) in x.iter().zip(positions(&mut sims[1])) {
                let d = p.distance(q);
                (lod, lod_max, n) = (lod + d as f64, lod_max.max(d), n + 1);
            }
        }
        let lod = lod / n as f64;
        eprintln!(
            "{backend:?}: root points within {worst:e} m of their frames; followers {lod:.2e} m (mean), {lod_max:.2e} m (most) from every strand simulated"
        );
        assert!(
            worst < 1e-6,
            "{backend:?}: an output root point is {worst} m off its frame"
        );
        assert!(
            lod < 1.2e-3,
            "{backend:?}: followers {lod} m from every strand simulated"
        );
        ends.push(x);
    }
    if let [c, gp] = &ends[..] {
        let gap = c.iter().zip(gp).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        eprintln!("guides on skinned roots: GPU output {gap:e} m from the CPU's");
        assert!(gap < 1e-4, "GPU output {gap} m from the CPU's");
    }
}

/// Frames that follow the head (each root placed and turned by the head's transform) give
/// the output the head gives, followers included: rounding apart, not physics apart.
#[test]
fn roots_that_follow_the_head_give_the_heads_followers() {
    let _serial = serial();
    let g = sheet();
    let head_at =
        |t: f32| Mat4::from_rotation_translation(Quat::from_rotation_x(0.8 * t), Vec3::new(0.1 * t, 0.0, 0.05 * t));
    for backend in backends() {
        let mut by_head = Simulation::new(
            &g,
            SimParams {
                skinned_roots: false,
                ..params(backend, quarter())
            },
        )
        .unwrap();
        let mut by_roots = Simulation::new(&g, params(backend, quarter())).unwrap();
        for f in 1..=60 {
            let m = head_at(f as f32 * DT);
            by_head.set_head_transform(m).unwrap();
            by_roots.set_root_frames(&frames_on_head(&g, m)).unwrap();
            by_head.step(DT).unwrap();
            by_roots.step(DT).unwrap();
        }
        let (a, b) = (positions(&mut by_head), positions(&mut by_roots));
        let gap = a.iter().zip(&b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max);
        eprintln!("{backend:?}: followers by roots {gap:e} m from followers by the head");
        assert!(
            gap < 1e-5,
            "{backend:?}: followers by roots ended {gap} m from the head's"
        );
    }
}

/// A jump of 2 m (and a half turn) past the teleport distance: the guides arrive at rest (no
/// velocity spike), and every output point, followers' included, lies within a strand's
/// length of its own new root, the root points on their frames.
#[test]
fn a_teleport_carries_guides_and_followers() {
    let _serial = serial();
    let g = sheet();
    let away = Vec3::new(2.0, -1.0, 0.5);
    let turn = Quat::from_rotation_z(1.5);
    for backend in backends() {
        let mut sim = Simulation::new(&g, params(backend, quarter())).unwrap();
        for f in 1..=30 {
            sim.set_root_frames(&skin(&g, f as f32 * DT)).unwrap();
            sim.step(DT).unwrap();
        }
        let jumped = frames_moved(&skin(&g, 31.0 * DT), turn, away);
        sim.set_root_frames(&jumped).unwrap();
        sim.step(DT).unwrap();
        let speed = sim.velocities().iter().map(|v| v.length()).fold(0.0, f32::max);
        let x = positions(&mut sim);
        let err = root_error(&x, &g, &jumped);
        let far = (0..g.strand_count())
            .flat_map(|s| {
                let root = jumped[s].position;
                x[g.strand_range(s)]
                    .iter()
                    .map(move |p| p.distance(root))
                    .collect::<Vec<_>>()
            })
            .fold(0.0, f32::max);
        eprintln!("{backend:?}: after the jump, guides at {speed} m/s, roots {err:e} m off, points within {far} m of their roots");
        assert!(speed < 2.0, "{backend:?}: a guide moves at {speed} m/s after the jump");
        assert!(err < 1e-6, "{backend:?}: a root point is {err} m off its frame");
        assert!(
            far < 0.15,
            "{backend:?}: a point is {far} m from its root (strands are 0.11 m)"
        );
    }
}

/// Raising the simulated fraction with no blend: the guides that start to be simulated start
/// where the output showed them, roots on their frames, so the output does not move at the
/// change.
#[test]
fn new_guides_start_where_the_output_showed_them() {
    let _serial = serial();
    let g = sheet();
    for backend in backends() {
        let guides = Guides {
            fraction: 0.25,
            blend_time: 0.0,
            ..Guides::every_nth(1)
        };
        let mut sim = Simulation::new(&g, params(backend, guides)).unwrap();
        for f in 1..=30 {
            sim.set_root_frames(&skin(&g, f as f32 * DT)).unwrap();
            sim.step(DT).unwrap();
        }
        let before = positions(&mut sim);
        sim.set_guide_fraction(1.0).unwrap();
        assert_eq!(sim.guide_counts(), Some((256, 256)));
        let after = positions(&mut sim);
        let moved = before
            .iter()
            .zip(&after)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f32::max);
        eprintln!("{backend:?}: the output moved {moved:e} m as the fraction rose");
        assert!(moved < 1e-6, "{backend:?}: the output moved {moved} m at the change");
    }
}

/// Fixed steps with interpolated output at a 144 Hz host, from a reset onto the moving skin:
/// with every strand a guide, the followers' output (roots shown between the last two steps'
/// frames, turned by slerp) is the plain simulation's blend (points moved in straight lines)
/// within 2e-6 m, the gap between a chord and an arc; showing the last step's frames instead
/// would be off by up to a step's motion (about 1e-3 m here).
#[test]
fn followers_show_the_roots_between_the_last_two_steps() {
    let _serial = serial();
    let g = sheet();
    for backend in backends() {
        let out = |guides: Guides| {
            let p = SimParams {
                fixed_step: FixedStep::every(1.0 / 120.0),
                ..params(backend, guides)
            };
            let mut sim = Simulation::new(&g, p).unwrap();
            sim.set_root_frames(&skin(&g, 0.0)).unwrap();
            sim.reset().unwrap();
            let mut frames = Vec::new();
            for f in 1..=30 {
                sim.set_root_frames(&skin(&g, f as f32 / 144.0)).unwrap();
                sim.advance(1.0 / 144.0).unwrap();
                frames.push(positions(&mut sim));
            }
            frames
        };
        let (plain, all) = (out(Guides::ALL), out(Guides::every_nth(1)));
        let gap = plain
            .iter()
            .zip(&all)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| p.distance(*q)))
            .fold(0.0, f32::max);
        eprintln!("{backend:?}: followers' fixed-step blend {gap:e} m from the plain one");
        assert!(
            gap < 2e-6,
            "{backend:?}: the followers' blend is {gap} m from the plain one"
        );
    }
}

/// The same frames on 1 and 2 CPU threads give the same output, bit for bit.
#[test]
fn guides_on_skinned_roots_repeat_on_any_thread_count() {
    let _serial = serial();
    let g = sheet();
    let run = |threads: u32| {
        let mut sim = Simulation::new(
            &g,
            SimParams {
                threads,
                ..params(Backend::CPU, quarter())
            },
        )
        .unwrap();
        for f in 1..=30 {
            sim.set_root_frames(&skin(&g, f as f32 * DT)).unwrap();
            sim.step(DT).unwrap();
        }
        positions(&mut sim)
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert!(run(1) == run(2), "1 and 2 threads differ");
}
