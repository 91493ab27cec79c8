//! Prints sanity numbers for the paper scene after N frames, and the tip positions
//! of the first strands, to check wethair against another engine run on the same scene (`docs/METHOD.md` §6).
//! Usage: cargo run --release --example sanity -- [frames] [threads]
use wethair::{groom::paper_scene, SimParams, Simulation};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let frames: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(110);
    let threads: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    let groom = paper_scene(10_000, 6).unwrap();
    let mut sim = Simulation::new(
        &groom,
        SimParams {
            threads,
            ..SimParams::paper()
        },
    )
    .unwrap();
    let t0 = std::time::Instant::now();
    for _ in 0..frames {
        sim.step(1.0 / 60.0).unwrap();
    }
    let ms = t0.elapsed().as_secs_f64() * 1e3 / frames as f64;
    let x = sim.positions();
    let max_abs = x.iter().map(|p| p.abs().max_element()).fold(0.0f32, f32::max);
    let max_r = x.iter().map(|p| p.length()).fold(0.0f32, f32::max);
    let mut strain = 0.0f32;
    for s in 0..10_000 {
        for i in 0..5 {
            strain = strain.max((x[s * 6 + i + 1] - x[s * 6 + i]).length() / 0.02 - 1.0);
        }
    }
    println!("frames {frames}: max_abs {max_abs:.3} max_r {max_r:.3} max_strain {strain:.3}  {ms:.3} ms/frame");
    for s in [0usize, 1, 5000, 9999] {
        println!("tip {s}: {:?}", x[s * 6 + 5]);
    }
}
