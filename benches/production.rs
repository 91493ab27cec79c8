//! The production features' cost (issue 17) on a 100,000-strand groom (the paper scene's
//! generator, 16 points a strand), on each backend that starts: every strand simulated, then
//! guides at 25% and 10% (followers written from them), 10% with hair-hair volume, every
//! strand with hair-hair volume, an SDF head, or skinned roots, and 10% with skinned roots. A frame is one step of 1/60 s
//! (4 substeps, symplectic Euler) plus the copy of every strand's vertices to the host (which
//! also waits for the GPU); median over the timed frames after a warm-up. On a GPU with
//! timestamp queries a last column gives the GPU time of the step itself (median of 5 more
//! steps), which the frame's vertex copy hides. A second table
//! times a change of the simulated fraction (binding every strand again; on the GPU it also
//! reads the guides back to start the new ones).
//!
//! Run: `cargo bench --bench production` (about two minutes here), or `-- --quick`.

use glam::{Quat, Vec3};
use std::time::Instant;
use wethair::groom::{paper_scene, Groom};
use wethair::physics::roots::RootFrame;
use wethair::physics::sdf::Sdf;
use wethair::{Backend, Guides, Integrator, SimParams, Simulation, Volume};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

/// One configuration: its name and how it changes the parameters.
struct Row {
    name: &'static str,
    edit: fn(&mut SimParams),
    roots: bool,
}

/// A sphere of radius 0.1 m (the paper scene's head) sampled every 5 mm.
fn head_sdf() -> Sdf {
    let (radius, cell) = (0.1f32, 0.005f32);
    let half = radius + 2.0 * cell;
    let n = (2.0 * half / cell).ceil() as u32 + 1;
    Sdf::from_fn([n; 3], Vec3::splat(-half), cell, |p| p.length() - radius)
}

fn rows() -> Vec<Row> {
    vec![
        Row {
            name: "every strand",
            edit: |_| {},
            roots: false,
        },
        Row {
            name: "guides 25%",
            edit: |p| p.guides = Guides::every_nth(4),
            roots: false,
        },
        Row {
            name: "guides 10%",
            edit: |p| p.guides = Guides::every_nth(10),
            roots: false,
        },
        Row {
            name: "guides 10% + volume",
            edit: |p| {
                p.guides = Guides::every_nth(10);
                p.volume = Volume::ON;
            },
            roots: false,
        },
        Row {
            name: "every strand + volume",
            edit: |p| p.volume = Volume::ON,
            roots: false,
        },
        Row {
            name: "every strand + SDF head (44³)",
            edit: |p| {
                p.colliders.clear();
                p.sdfs = vec![std::sync::Arc::new(head_sdf())];
            },
            roots: false,
        },
        Row {
            name: "every strand, skinned roots",
            edit: |p| p.skinned_roots = true,
            roots: true,
        },
        Row {
            name: "guides 10%, skinned roots",
            edit: |p| {
                p.guides = Guides::every_nth(10);
                p.skinned_roots = true;
            },
            roots: true,
        },
    ]
}

fn params(backend: Backend, cores: u32) -> SimParams {
    SimParams {
        backend,
        threads: cores,
        integrator: Integrator::SYMPLECTIC_EULER,
        substeps: 4,
        ..SimParams::paper_scene_with_head()
    }
}

/// Median ms per frame (step and vertex copy), of the step alone, the strands simulated, and
/// on a GPU with timestamps the median GPU time of the step itself (5 more steps, each read
/// back before the next).
fn time_row(
    groom: &Groom,
    row: &Row,
    backend: Backend,
    cores: u32,
    frames: usize,
) -> Option<(f64, f64, usize, Option<f64>)> {
    let mut p = params(backend, cores);
    (row.edit)(&mut p);
    let mut sim = match Simulation::new(groom, p) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{backend:?} {}: {e}", row.name);
            return None;
        }
    };
    let simulated = sim.guide_counts().map_or(groom.strand_count(), |c| c.0);
    let roots: Vec<RootFrame> = (0..groom.strand_count())
        .map(|s| RootFrame {
            position: groom.positions()[groom.strand_range(s).start],
            rotation: Quat::IDENTITY,
        })
        .collect();
    let mut out = vec![0.0f32; sim.vertex_count() * sim.attributes().stride()];
    let (mut times, mut steps) = (Vec::new(), Vec::new());
    for f in 0..frames + 3 {
        let t0 = Instant::now();
        if row.roots {
            sim.set_root_frames(&roots).expect("roots");
        }
        sim.step(1.0 / 60.0).expect("step");
        let t1 = Instant::now();
        sim.write_vertices(&mut out).expect("vertices");
        if f >= 3 {
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            steps.push((t1 - t0).as_secs_f64() * 1e3);
        }
    }
    let mut gpu = Vec::new();
    if backend == Backend::GPU && sim.enable_gpu_timing() {
        for _ in 0..5 {
            if row.roots {
                sim.set_root_frames(&roots).expect("roots");
            }
            sim.step(1.0 / 60.0).expect("step");
            if let Some(Ok(ms)) = sim.last_step_gpu_ms() {
                gpu.push(ms);
            }
        }
    }
    let gpu = (!gpu.is_empty()).then(|| median(gpu));
    Some((median(times), median(steps), simulated, gpu))
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let groom = paper_scene(100_000, 16).expect("groom");
    let frames = if quick { 5 } else { 20 };
    println!("Production features on a 100,000 x 16 groom (median ms/frame: a 1/60 s step in 4 substeps plus every strand's vertices copied to the host; CPU on {cores} threads):");
    println!();
    println!("| configuration | backend | strands simulated | ms/frame | over every strand | step ms (the GPU's: encoding) | GPU step ms (timestamps) |");
    println!("|---|---|---|---|---|---|---|");
    let mut backends = vec![Backend::CPU];
    if Simulation::new(&paper_scene(8, 3).unwrap(), params(Backend::GPU, 1)).is_ok() {
        backends.push(Backend::GPU);
    }
    for &backend in &backends {
        let mut base = None;
        for row in rows() {
            let Some((ms, step, n, gpu)) = time_row(&groom, &row, backend, cores, frames) else {
                continue;
            };
            let b = *base.get_or_insert(ms);
            let gpu = gpu.map_or("-".to_string(), |g| format!("{g:.2}"));
            println!(
                "| {} | {backend:?} | {n} | {ms:.1} | {:.2} | {step:.1} | {gpu} |",
                row.name,
                ms / b
            );
        }
    }
    println!();
    println!("A change of the simulated fraction (guides every 4th strand: 25,000; ms, once):");
    println!();
    println!("| change | backend | ms |");
    println!("|---|---|---|");
    for &backend in &backends {
        let mut p = params(backend, cores);
        p.guides = Guides::every_nth(4);
        let mut sim = Simulation::new(&groom, p).expect("sim");
        sim.step(1.0 / 60.0).expect("step");
        for (name, f) in [("100% -> 40%", 0.4f32), ("40% -> 100%", 1.0)] {
            let t0 = Instant::now();
            sim.set_guide_fraction(f).expect("fraction");
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            println!("| {name} | {backend:?} | {ms:.1} |");
            for _ in 0..20 {
                sim.step(1.0 / 60.0).expect("step");
            }
        }
    }
}
