//! ms/frame benchmark: the paper scene (10,000 × 6) dry and with 20..1,000 water particles,
//! single- and multi-threaded, and the big scene (100,000 × 16), on the CPU backend.
//! Median over the timed frames after a warm-up; prints a markdown table with the passes and
//! the memory each scene uses (what a scene leaves out shows here too).
//!
//! Run: `cargo bench --bench frame` (full, about a minute), or `-- --quick` (fewer frames).

use std::time::Instant;
use wethair::groom::{paper_scene, Groom};
use wethair::scenes::{on_hair, Lcg};
use wethair::{SimParams, Simulation};

struct Row {
    scene: String,
    particles: usize,
    threads: u32,
    collider: bool,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn run(groom: &Groom, row: &Row, frames: usize, warmup: usize) -> (f64, f64, String, f64, usize) {
    let params = if row.collider {
        SimParams::paper_scene_with_head()
    } else {
        SimParams::default()
    };
    let mut sim = Simulation::new(
        groom,
        SimParams {
            threads: row.threads,
            ..params
        },
    )
    .expect("sim");
    if row.particles > 0 {
        let water = on_hair(groom.positions(), row.particles, &mut Lcg(2024));
        sim.add_water(&water, &[]).expect("water");
    }
    let mut times = Vec::with_capacity(frames);
    for f in 0..warmup + frames {
        let t0 = Instant::now();
        sim.step(1.0 / 60.0).expect("step");
        if f >= warmup {
            times.push(t0.elapsed().as_secs_f64() * 1e3);
        }
    }
    let passes: Vec<&str> = sim.passes().iter().map(|p| p.name()).collect();
    let mib = sim.buffers().iter().map(|b| b.1).sum::<usize>() as f64 / (1 << 20) as f64;
    let held = sim.stats().particles as usize;
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    (median(times), mean, passes.join(" "), mib, held)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let (frames, warmup) = if quick { (60, 5) } else { (200, 10) };
    let paper = paper_scene(10_000, 6).expect("paper scene");
    let mut rows = vec![];
    for threads in [1, cores] {
        rows.push(Row {
            scene: "paper 10000x6".into(),
            particles: 0,
            threads,
            collider: false,
        });
    }
    rows.push(Row {
        scene: "paper 10000x6".into(),
        particles: 0,
        threads: cores,
        collider: true,
    });
    for threads in [1, cores] {
        for particles in [20, 40, 60, 80, 100, 1000] {
            rows.push(Row {
                scene: "paper 10000x6".into(),
                particles,
                threads,
                collider: true,
            });
        }
    }
    println!(
        "wethair {} CPU backend, {cores} cores; frame = 1/60 s in 4 substeps; median of {frames} frames after {warmup}",
        env!("CARGO_PKG_VERSION")
    );
    println!();
    println!("| scene | water particles (held at end) | head collider | threads | ms/frame median | mean | passes per substep | memory MiB |");
    println!("|---|---|---|---|---|---|---|---|");
    for row in &rows {
        let (med, mean, passes, mib, held) = run(&paper, row, frames, warmup);
        let water = if row.particles > 0 {
            format!("{} ({held})", row.particles)
        } else {
            "0".into()
        };
        println!(
            "| {} | {water} | {} | {} | {med:.3} | {mean:.3} | {passes} | {mib:.1} |",
            row.scene,
            if row.collider { "yes" } else { "no" },
            row.threads
        );
    }
    let big = paper_scene(100_000, 16).expect("big scene");
    let big_frames = if quick { 20 } else { 200 };
    for threads in [1, cores] {
        let row = Row {
            scene: "big 100000x16".into(),
            particles: 0,
            threads,
            collider: false,
        };
        let (med, mean, passes, mib, _) = run(&big, &row, big_frames, 5);
        println!(
            "| {} | 0 | no | {} | {med:.3} | {mean:.3} | {passes} | {mib:.1} |",
            row.scene, row.threads
        );
    }
}
