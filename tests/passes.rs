//! Leave out what a scene does not need: the pass list and the buffers follow the scene.

use glam::Vec3;
use wethair::groom::paper_scene;
use wethair::plan::Pass;
use wethair::{Shape, SimParams, Simulation, SpringParams};

#[test]
fn dry_scene_has_no_water_passes_or_buffers() {
    let groom = paper_scene(100, 6).unwrap();
    let sim = Simulation::new(&groom, SimParams::paper()).unwrap();
    assert_eq!(
        sim.passes(),
        vec![Pass::StretchSprings, Pass::BendSprings, Pass::Integrate]
    );
    let names: Vec<_> = sim.buffers().iter().map(|b| b.0).collect();
    assert!(
        !names.iter().any(|n| n.starts_with("water") || *n == "wetness"),
        "{names:?}"
    );
}

#[test]
fn passes_appear_only_with_their_feature() {
    let groom = paper_scene(100, 6).unwrap();
    let params = SimParams {
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
    assert!(names.contains(&"water_grid") && names.contains(&"wetness"));
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
            threads: 1,
            ..SimParams::paper()
        },
    )
    .unwrap();
    let mut b = Simulation::new(
        &groom,
        SimParams {
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
