//! Scratch: fixed cost of the wet path.
use glam::Vec3;
use wethair::{groom::paper_scene, SimParams, Simulation};
fn main() {
    let groom = paper_scene(10_000, 6).unwrap();
    let mut p = SimParams::paper_scene_with_head();
    p.gravity = Vec3::ZERO;
    let mut dry = Simulation::new(&groom, p.clone()).unwrap();
    let t = std::time::Instant::now();
    for _ in 0..200 { dry.step(1.0/60.0).unwrap(); }
    println!("dry with collider: {:.3} ms/frame", t.elapsed().as_secs_f64()*1e3/200.0);
    let mut sim = Simulation::new(&groom, p).unwrap();
    sim.add_water(&[Vec3::new(0.0, 0.0, -0.2)], &[]).unwrap();
    let t = std::time::Instant::now();
    for _ in 0..200 { sim.step(1.0/60.0).unwrap(); }
    println!("1 far particle: {:.3} ms/frame, particles {}", t.elapsed().as_secs_f64()*1e3/200.0, sim.stats().particles);
}
