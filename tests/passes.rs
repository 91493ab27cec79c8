//! Leave out what a scene does not need: the pass list and the buffers follow the scene.
//!
//! On each backend: a default-backend scene would test the GPU on a real GPU and the CPU on
//! lavapipe (AUTO passes over software adapters), so each backend is named.

use crate::common::{backends, serial};
use glam::Vec3;
use wethair::groom::paper_scene;
use wethair::plan::Pass;
use wethair::{Backend, Shape, SimParams, Simulation, SpringParams};

#[test]
fn dry_scene_has_no_water_passes_or_buffers() {
    let _serial = serial();
    let groom = paper_scene(100, 6).unwrap();
    for backend in backends() {
        let p = SimParams {
            backend,
            ..SimParams::paper()
        };
        let sim = Simulation::new(&groom, p).unwrap();
        assert_eq!(
            sim.passes(),
            vec![Pass::StretchSprings, Pass::BendSprings, Pass::Integrate]
        );
        let names: Vec<_> = sim.buffers().iter().map(|b| b.0).collect();
        assert!(
            !names.iter().any(|n| n.starts_with("water") || *n == "wetness"),
            "{backend:?}: {names:?}"
        );
    }
}

#[test]
fn passes_appear_only_with_their_feature() {
    let _serial = serial();
    for backend in backends() {
        passes_follow_the_features(backend);
    }
}

fn passes_follow_the_features(backend: Backend) {
    let groom = paper_scene(100, 6).unwrap();
    let params = SimParams {
        backend,
        bend: SpringParams {
            stiffness: 0.0,
            damping: 0.0,
        },
        air_drag: 0.01,
        colliders: vec![Shape::Capsule {
            a: Vec3::ZERO,
            b: Vec3::Z * 0.1,
            radius: 0.05,
        }],
        ..SimParams::paper()
    };
    let mut sim = Simulation::new(&groom, params).unwrap();
    assert_eq!(
        sim.passes(),
        vec![Pass::Drag, Pass::StretchSprings, Pass::Integrate, Pass::Collide]
    );
    sim.add_water(&[Vec3::new(0.0, 0.0, 0.25)], &[]).unwrap();
    assert_eq!(
        sim.passes(),
        vec![
            Pass::WaterGrid,
            Pass::Drag,
            Pass::StretchSprings,
            Pass::Adhesion,
            Pass::Integrate,
            Pass::Collide,
            Pass::WaterIntegrate,
            Pass::WaterCull
        ]
    );
    let names: Vec<_> = sim.buffers().iter().map(|b| b.0).collect();
    assert!(
        names.contains(&"water_grid") && names.contains(&"water_particles"),
        "{backend:?}: {names:?}"
    );
    // The CPU keeps the paper's wetness per point in its own buffer; the GPU in the state.
    assert_eq!(names.contains(&"wetness"), backend == Backend::CPU, "{names:?}");
    // Water gone: its passes go too (buffers stay for the next shower).
    sim.clear_water().unwrap();
    assert!(!sim.passes().contains(&Pass::Adhesion));
}

#[test]
fn particles_leaving_the_domain_are_removed() {
    let groom = paper_scene(100, 6).unwrap();
    let mut sim = Simulation::new(&groom, SimParams::paper()).unwrap();
    // Domain radius defaults to half the groom's diagonal plus its longest strand (~0.4 m).
    sim.add_water(
        &[Vec3::new(0.0, 0.0, 0.25), Vec3::new(0.0, 0.0, -0.45)],
        &[Vec3::ZERO, Vec3::new(0.0, 0.0, -5.0)],
    )
    .unwrap();
    sim.step(1.0 / 60.0).unwrap();
    let st = sim.stats();
    assert_eq!((st.particles, st.particles_removed), (1, 1));
}

#[test]
fn single_and_multi_threaded_steps_agree_exactly_when_dry() {
    let groom = paper_scene(1000, 6).unwrap();
    let mut a = Simulation::new(
        &groom,
        SimParams {
            backend: Backend::CPU,
            threads: 1,
            ..SimParams::paper()
        },
    )
    .unwrap();
    let mut b = Simulation::new(
        &groom,
        SimParams {
            backend: Backend::CPU,
            threads: 2,
            ..SimParams::paper()
        },
    )
    .unwrap();
    for _ in 0..30 {
        a.step(1.0 / 60.0).unwrap();
        b.step(1.0 / 60.0).unwrap();
    }
    assert_eq!(a.positions(), b.positions());
    assert_eq!(b.stats().threads, 2);
}

/// The step's own pass timers: off by default (nothing timed), on they name the stages a
/// scene runs, in step order, each run as often as the plan says (per substep or per step),
/// and a dry scene times no water stage; switching on again starts from zero.
#[test]
fn pass_timers_follow_the_scene() {
    // Dense enough that soaked points of different strands lie within the bridge length.
    let groom = paper_scene(10_000, 6).unwrap();
    let params = SimParams {
        backend: wethair::Backend::CPU,
        held_water: wethair::HeldWater::ON,
        ..SimParams::paper_scene_with_head()
    };
    let substeps = params.substeps as u64;
    let mut sim = Simulation::new(&groom, params).unwrap();
    sim.step(1.0 / 60.0).unwrap();
    assert!(sim.pass_times().is_empty(), "timed while off");
    assert!(sim.time_passes(true));
    sim.step(1.0 / 60.0).unwrap();
    let names: Vec<_> = sim.pass_times().iter().map(|p| p.name).collect();
    assert_eq!(
        names,
        ["wet_params", "hair_grid", "blocks", "flow", "drip", "dry"],
        "dry hair"
    );
    sim.soak(1.0).unwrap();
    // A soaking's points search for bridges first on their turns (`wet::bridge_searches`):
    // after a round of turns every step has bridges to pull.
    for _ in 0..wethair::physics::wet::BRIDGE_SEARCH_TURNS {
        sim.step(1.0 / 60.0).unwrap();
    }
    let x = sim.positions();
    sim.add_water(&x[100..110], &[]).unwrap();
    assert!(sim.time_passes(true));
    let steps = 3;
    for _ in 0..steps {
        sim.step(1.0 / 60.0).unwrap();
    }
    let mut out = vec![0.0; sim.vertex_count() * sim.attributes().stride()];
    sim.write_vertices(&mut out).unwrap();
    let t = sim.pass_times();
    let names: Vec<_> = t.iter().map(|p| p.name).collect();
    assert_eq!(
        names,
        [
            "wet_params",
            "hair_grid",
            "water_grid",
            "cohesion",
            "blocks",
            "absorb",
            "water_integrate",
            "flow",
            "drip",
            "dry",
            "water_cull",
            "vertices"
        ]
    );
    for p in &t {
        // On the CPU, `cohesion` packs the wet points' positions once a step; the block
        // kernel pulls them (inside `blocks`) and writes the next substep's.
        let per_substep = ["water_grid", "blocks", "absorb", "water_integrate"].contains(&p.name);
        let want = match p.name {
            "vertices" => 1,
            _ if per_substep => steps * substeps,
            _ => steps,
        };
        assert_eq!(p.runs, want, "{}", p.name);
        assert!(p.ms.is_finite() && p.ms >= 0.0, "{}: {}", p.name, p.ms);
    }
    assert!(sim.time_passes(false));
    sim.step(1.0 / 60.0).unwrap();
    assert!(sim.pass_times().is_empty(), "timed while off");
}
