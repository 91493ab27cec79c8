//! ms/frame benchmark: the paper scene (10,000 × 6) dry and with 20..1,000 water particles
//! (1,000 also with drops that meet coalescing), single- and multi-threaded, and the big scene (100,000 × 16), on the CPU backend.
//! Median over the timed frames after a warm-up; prints a markdown table with the passes and
//! the memory each scene uses (what a scene leaves out shows here too).
//!
//! A second table times every integrator per groom (the paper scene, the real grooms in
//! `tests/data`, a long-strand paper scene) and gives each one's cost against symplectic Euler.
//!
//! Run: `cargo bench --bench frame` (full, about a minute), or `-- --quick` (fewer frames).
//! Name sections to run only those: `-- --quick wet copy` (sections: `frames`, `integrators`,
//! `wet`, `particles`, `copy`, `estimate`, `auto`, `colliders`). `-- wet --gpu` adds the GPU backend's rows
//! to the wet model's table (left out by default: slow on a software adapter).
//!
//! `particles` (run only when named: `-- --quick particles`, about seven minutes here) times the
//! water's cost against the particle count (0 to 1,000,000) on the paper scene and a
//! 100,000 x 16 groom, with the paper's model and the full wet model.

use std::time::Instant;
use wethair::groom::{paper_scene, Groom};
use wethair::scenes::{on_hair, Lcg};
use wethair::{Integrator, PassTime, SimParams, Simulation};

struct Row {
    scene: String,
    particles: usize,
    threads: u32,
    collider: bool,
    /// `WaterParams::pile_cell`, m (0: drops pass through each other).
    pile_cell: f32,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn run(groom: &Groom, row: &Row, frames: usize, warmup: usize) -> (f64, f64, String, f64, usize) {
    run_with(groom, row, Integrator::SYMPLECTIC_EULER, frames, warmup)
}

fn run_with(
    groom: &Groom,
    row: &Row,
    integrator: Integrator,
    frames: usize,
    warmup: usize,
) -> (f64, f64, String, f64, usize) {
    let params = if row.collider {
        SimParams::paper_scene_with_head()
    } else {
        SimParams::paper()
    };
    let mut params = SimParams { integrator, ..params };
    params.water.pile_cell = row.pile_cell;
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

/// What [`timed_frames`] measured.
struct Timed {
    /// Median ms/frame.
    ms: f64,
    /// Particles at the end.
    particles: u32,
    /// Particles over the timed frames, mean (each frame's count after its step): where the
    /// hair soaks drops up, what the frames actually carried.
    mean_particles: f64,
    /// Adhesion pairs a timed frame, mean (`Stats::adhesion_pairs`: the water's work).
    mean_pairs: f64,
    passes: Vec<PassTime>,
}

/// Steps `warmup` frames, then `frames` more with the pass timers on.
fn timed_frames(sim: &mut Simulation, warmup: usize, frames: usize) -> Timed {
    let mut times = Vec::with_capacity(frames);
    let (mut carried, mut pairs) = (0u64, 0u64);
    for f in 0..warmup + frames {
        if f == warmup {
            sim.time_passes(true);
        }
        let t0 = Instant::now();
        sim.step(1.0 / 60.0).expect("step");
        if f >= warmup {
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            // The counters alone: `stats` would also measure the clumping, a search over the
            // strands between two timed steps that leaves the next step a cold cache.
            let c = sim.counters();
            (carried, pairs) = (carried + c.particles as u64, pairs + c.adhesion_pairs);
        }
    }
    Timed {
        ms: median(times),
        particles: sim.counters().particles,
        mean_particles: carried as f64 / frames.max(1) as f64,
        mean_pairs: pairs as f64 / frames.max(1) as f64,
        passes: sim.pass_times(),
    }
}

fn section(name: &str) -> bool {
    const SECTIONS: [&str; 8] = [
        "frames",
        "integrators",
        "wet",
        "particles",
        "copy",
        "estimate",
        "auto",
        "colliders",
    ];
    // Run unless named: every section but `particles` (a quarter of an hour here).
    const BY_NAME_ONLY: [&str; 1] = ["particles"];
    let named: Vec<String> = std::env::args().filter(|a| SECTIONS.contains(&a.as_str())).collect();
    (named.is_empty() && !BY_NAME_ONLY.contains(&name)) || named.iter().any(|a| a == name)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let (frames, warmup) = if quick { (60, 5) } else { (200, 10) };
    if section("frames") {
        frame_rows(cores, frames, warmup, quick);
    }
    if section("integrators") {
        integrator_costs(cores, quick);
    }
    if section("wet") {
        wet_model_costs(cores, quick);
    }
    if section("particles") {
        particle_scaling(cores, quick);
    }
    if section("copy") {
        copy_path_cost(cores, quick);
    }
    if section("estimate") {
        estimate_cost(cores, frames, warmup);
    }
    if section("auto") {
        auto_cost(cores, frames);
    }
    if section("colliders") {
        collider_frames_cost(cores, frames);
    }
}

/// Colliders on their own frames against the same colliders on the head: the paper scene
/// (10,000 x 6, dry) under a turning head with a head sphere and 15 capsules around it (a
/// collar, shoulders), each placed every substep; on frames, the host moves every frame to the
/// head's transform each frame, so both runs collide alike and the difference is the frames'
/// own cost. Frames interleaved.
fn collider_frames_cost(cores: u32, frames: usize) {
    use glam::{Affine3A, Mat4, Quat, Vec3};
    let groom = paper_scene(10_000, 6).expect("groom");
    let mut shapes = vec![wethair::Shape::Sphere {
        center: Vec3::ZERO,
        radius: 0.1,
    }];
    for k in 0..15 {
        let a = k as f32 * std::f32::consts::TAU / 15.0;
        let (s, c) = a.sin_cos();
        shapes.push(wethair::Shape::Capsule {
            a: Vec3::new(0.12 * c, 0.12 * s, -0.08),
            b: Vec3::new(0.2 * c, 0.2 * s, -0.12),
            radius: 0.025,
        });
    }
    let runs: [(&str, Vec<wethair::Shape>, bool); 3] = [
        ("head sphere only", shapes[..1].to_vec(), false),
        ("16 colliders on the head", shapes.clone(), false),
        ("16 colliders on their own frames", shapes.clone(), true),
    ];
    let mut sims: Vec<Simulation> = runs
        .iter()
        .map(|(_, colliders, on_frames)| {
            let p = SimParams {
                threads: cores,
                backend: wethair::Backend::CPU,
                collider_frames: if *on_frames {
                    vec![Affine3A::IDENTITY; colliders.len()]
                } else {
                    Vec::new()
                },
                colliders: colliders.clone(),
                ..SimParams::paper()
            };
            Simulation::new(&groom, p).expect("sim")
        })
        .collect();
    let mut times = vec![Vec::with_capacity(frames); runs.len()];
    for f in 0..10 + frames {
        let t = f as f32 / 60.0;
        let head = Mat4::from_rotation_translation(Quat::from_rotation_z(0.6 * (2.0 * t).sin()), Vec3::ZERO);
        for (k, sim) in sims.iter_mut().enumerate() {
            let t0 = Instant::now();
            sim.set_head_transform(head).expect("head");
            if runs[k].2 {
                for c in 0..runs[k].1.len() {
                    sim.set_collider_transform(c, head).expect("frame");
                }
            }
            sim.step(1.0 / 60.0).expect("step");
            if f >= 10 {
                times[k].push(t0.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    println!();
    println!("Colliders on frames, paper scene 10000x6 dry, turning head, {cores} threads, median of {frames} frames (interleaved):");
    println!();
    println!("| colliders | ms/frame |");
    println!("|---|---|");
    for (k, (name, _, _)) in runs.iter().enumerate() {
        println!("| {name} | {:.3} |", median(std::mem::take(&mut times[k])));
    }
}

/// AUTO under an error budget against fixed integrators on a stiff patch (1,000 strands of
/// the paper scene, springs 4000x the paper's: symplectic Euler needs 256 substeps of a
/// 60 Hz frame to be stable). Frames interleaved; timed after 3 s, once AUTO has settled.
fn auto_cost(cores: u32, frames: usize) {
    let sc = wethair::scenes::paper_slice(1000, 0, 4000.0);
    println!();
    println!(
        "AUTO under a 1e-4 m budget, paper patch 1000x6 at 4000x stiffness, CPU backend, {cores} threads, median of {frames} frames after 3 s (interleaved):"
    );
    println!();
    println!("| run | ms/frame | chose (frame: integrator x substeps) | estimate (RMS, max), m |");
    println!("|---|---|---|---|");
    let runs = [
        ("symplectic Euler x256", Integrator::SYMPLECTIC_EULER, 256, 0.0),
        ("BDF2 x1, fixed", Integrator::BDF2, 1, 0.0),
        ("AUTO, tolerance 1e-4 m", Integrator::AUTO, 256, 1e-4f32),
    ];
    let mut sims: Vec<Simulation> = runs
        .iter()
        .map(|&(_, integrator, substeps, tolerance)| {
            let p = SimParams {
                integrator,
                solver_iterations: 2,
                substeps,
                tolerance,
                max_substeps: 256,
                error_estimate_stride: 128,
                threads: cores,
                backend: wethair::Backend::CPU,
                ..sc.params.clone()
            };
            Simulation::new(&sc.groom, p).expect("sim")
        })
        .collect();
    let mut times = vec![Vec::with_capacity(frames); runs.len()];
    let mut chose = vec![vec![]; runs.len()];
    for f in 0..180 + frames {
        for (k, sim) in sims.iter_mut().enumerate() {
            let t0 = Instant::now();
            sim.step(1.0 / 60.0).expect("step");
            if f >= 180 {
                times[k].push(t0.elapsed().as_secs_f64() * 1e3);
            }
            let s = sim.counters(); // no measure between timed steps
            if chose[k].last().map(|c: &(usize, Integrator, u32)| (c.1, c.2)) != Some((s.integrator, s.substeps)) {
                chose[k].push((f, s.integrator, s.substeps));
            }
        }
    }
    for (k, sim) in sims.iter().enumerate() {
        let c: Vec<String> = chose[k].iter().map(|(f, i, n)| format!("{f}: {i:?} x{n}")).collect();
        let e = sim.stats().error_estimate;
        println!(
            "| {} | {:.3} | {} | {} |",
            runs[k].0,
            median(std::mem::take(&mut times[k])),
            c.join(", "),
            e.map_or("–".to_string(), |e| format!("{:.2e}, {:.2e}", e.rms, e.max))
        );
    }
}

/// The live error estimate's cost: the paper scene dry at every core, without it and with
/// every 128th and 32nd strand shadowed (frames interleaved: each configuration steps one frame
/// in turn, so a slow spell of the machine lands on all of them alike).
fn estimate_cost(cores: u32, frames: usize, warmup: usize) {
    let paper = paper_scene(10_000, 6).expect("paper scene");
    println!();
    println!("Live error estimate, paper 10000x6 dry, CPU backend, {cores} threads, median of {frames} frames (interleaved):");
    println!();
    println!("| integrator | stride | ms/frame | over no estimate | estimate (RMS, max) after the frames, m |");
    println!("|---|---|---|---|---|");
    for integrator in [Integrator::SYMPLECTIC_EULER, Integrator::BDF2] {
        let strides = [0u32, 128, 32];
        let mut sims: Vec<Simulation> = strides
            .iter()
            .map(|&error_estimate_stride| {
                Simulation::new(
                    &paper,
                    SimParams {
                        integrator,
                        solver_iterations: 2,
                        threads: cores,
                        error_estimate_stride,
                        ..SimParams::paper()
                    },
                )
                .expect("sim")
            })
            .collect();
        let mut times = vec![Vec::with_capacity(frames); strides.len()];
        for f in 0..warmup + frames {
            for (sim, t) in sims.iter_mut().zip(&mut times) {
                let t0 = Instant::now();
                sim.step(1.0 / 60.0).expect("step");
                if f >= warmup {
                    t.push(t0.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
        let ms: Vec<f64> = times.into_iter().map(median).collect();
        for (k, sim) in sims.iter().enumerate() {
            let e = sim.stats().error_estimate;
            println!(
                "| {integrator:?} | {} | {:.3} | {} | {} |",
                if strides[k] == 0 {
                    "off".to_string()
                } else {
                    strides[k].to_string()
                },
                ms[k],
                if k == 0 {
                    "–".to_string()
                } else {
                    format!("{:+.1}%", 100.0 * (ms[k] / ms[0] - 1.0))
                },
                e.map_or("–".to_string(), |e| format!("{:.2e}, {:.2e}", e.rms, e.max))
            );
        }
    }
}

/// The main table: the paper scene dry and wet at 1 and all threads, and the big scene dry.
fn frame_rows(cores: u32, frames: usize, warmup: usize, quick: bool) {
    let paper = paper_scene(10_000, 6).expect("paper scene");
    let mut rows = vec![];
    for threads in [1, cores] {
        rows.push(Row {
            scene: "paper 10000x6".into(),
            particles: 0,
            threads,
            collider: false,
            pile_cell: 0.0,
        });
    }
    rows.push(Row {
        scene: "paper 10000x6".into(),
        particles: 0,
        threads: cores,
        collider: true,
        pile_cell: 0.0,
    });
    for threads in [1, cores] {
        for particles in [20, 40, 60, 80, 100, 1000] {
            rows.push(Row {
                scene: "paper 10000x6".into(),
                particles,
                threads,
                collider: true,
                pile_cell: 0.0,
            });
        }
        // Drops that meet coalescing (`WaterParams::pile_cell`).
        rows.push(Row {
            scene: "paper 10000x6, drops coalescing in 0.1 mm cells".into(),
            particles: 1000,
            threads,
            collider: true,
            pile_cell: 1.0e-4,
        });
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
            pile_cell: 0.0,
        };
        let (med, mean, passes, mib, _) = run(&big, &row, big_frames, 5);
        println!(
            "| {} | 0 | no | {} | {med:.3} | {mean:.3} | {passes} | {mib:.1} |",
            row.scene, row.threads
        );
    }
}

/// The wet model's cost (issue 14): the paper scene with 1,000 particles on its hair, and a
/// 100,000 x 16 groom under rain, each dry, with the paper's model (adhesion only) and with
/// the full model (held water: absorption, weight, limpness, bridges, flow, drip, drying).
fn wet_model_costs(cores: u32, quick: bool) {
    use wethair::{Backend, HeldWater};
    // GPU rows only when asked: on a software adapter (lavapipe) the large groom's 300 frames
    // would take most of an hour.
    let gpu = std::env::args().any(|a| a == "--gpu");
    let backends: &[Backend] = if gpu {
        &[Backend::CPU, Backend::GPU]
    } else {
        &[Backend::CPU]
    };
    println!();
    println!("Wet model, {cores} CPU threads (median ms/frame; full / paper is the model's cost over the paper's wet step; a GPU frame is throughput: the frames' steps and one blocking read at the end, over the frame count):");
    println!();
    println!("| scene | backend | dry | paper model | full model | full / paper | particles at end (paper, full) |");
    println!("|---|---|---|---|---|---|---|");
    let frames = if quick { 40 } else { 200 };
    let time = |groom: &Groom,
                backend: Backend,
                wet: Option<bool>,
                water: &dyn Fn(&mut Simulation),
                frames: usize|
     -> Result<(f64, u32, Vec<PassTime>, String), String> {
        let mut p = SimParams {
            threads: cores,
            backend,
            ..SimParams::paper_scene_with_head()
        };
        if wet == Some(true) {
            p.held_water = HeldWater::ON;
        }
        let mut sim = Simulation::new(groom, p).map_err(|e| e.to_string())?;
        if wet.is_some() {
            water(&mut sim);
        }
        if backend == Backend::CPU {
            let Timed {
                ms,
                particles,
                passes: t,
                ..
            } = timed_frames(&mut sim, 5, frames);
            return Ok((ms, particles, t, "CPU".into()));
        }
        let (ms, particles, t) = gpu_frames(&mut sim, 5, frames);
        Ok((ms, particles, t, format!("GPU, {}", sim.backend_info().device)))
    };
    let paper = paper_scene(10_000, 6).expect("paper scene");
    let on_hair_1000 = |s: &mut Simulation| {
        let w = on_hair(s.positions().as_slice(), 1000, &mut Lcg(2024));
        s.add_water(&w, &[]).expect("water");
    };
    let big = paper_scene(100_000, 16).expect("big scene");
    let rain = |s: &mut Simulation| {
        s.set_rain(Some(wethair::scenes::rain_over_head())).expect("rain");
    };
    let big_frames = if quick { 20 } else { 100 };
    let mut split = Vec::new();
    for &backend in backends {
        for (name, groom, water, n) in [
            (
                "paper 10000x6, 1000 particles on hair",
                &paper,
                &on_hair_1000 as &dyn Fn(&mut Simulation),
                frames,
            ),
            ("100000x16 under rain (100 drops a frame)", &big, &rain, big_frames),
        ] {
            let rows = (|| -> Result<_, String> {
                Ok((
                    time(groom, backend, None, water, n)?,
                    time(groom, backend, Some(false), water, n)?,
                    time(groom, backend, Some(true), water, n)?,
                ))
            })();
            let ((dry, _, t_dry, device), (paper_ms, pp, t_paper, _), (full_ms, pf, t_full, _)) = match rows {
                Ok(r) => r,
                Err(e) => {
                    println!("| {name} | {backend:?} | no row: {e} | | | | |");
                    continue;
                }
            };
            println!(
                "| {name} | {device} | {dry:.2} | {paper_ms:.2} | {full_ms:.2} | {:.2} | {pp}, {pf} |",
                full_ms / paper_ms
            );
            // The GPU's split is its own time by timestamps, over the extra steps.
            let (split_frames, models) = if backend == Backend::CPU {
                (n, ["dry", "paper", "full"])
            } else {
                (GPU_SPLIT_FRAMES, ["dry (GPU)", "paper (GPU)", "full (GPU)"])
            };
            for (model, t) in models.into_iter().zip([t_dry, t_paper, t_full]) {
                split.push((name, model, split_frames, t));
            }
        }
    }
    print_pass_split(&split);
}

/// Steps a GPU timestamps the stage split over, after its throughput frames.
const GPU_SPLIT_FRAMES: usize = 20;

/// A GPU simulation's frames: `warmup`, then `frames` timed as throughput (their steps and one
/// blocking read, over `frames`), then [`GPU_SPLIT_FRAMES`] more with the stage timestamps on
/// (each of those waits for its stamps, so they are not in the ms/frame). The stage split is
/// empty where the adapter cannot write timestamps inside a pass.
fn gpu_frames(sim: &mut Simulation, warmup: usize, frames: usize) -> (f64, u32, Vec<PassTime>) {
    for _ in 0..warmup {
        sim.step(1.0 / 60.0).expect("step");
    }
    let _ = sim.positions();
    let t0 = Instant::now();
    for _ in 0..frames {
        sim.step(1.0 / 60.0).expect("step");
    }
    let _ = sim.positions();
    let ms = t0.elapsed().as_secs_f64() * 1e3 / frames as f64;
    let particles = sim.stats().particles;
    let mut split = Vec::new();
    if sim.time_passes(true) {
        for _ in 0..GPU_SPLIT_FRAMES {
            sim.step(1.0 / 60.0).expect("step");
        }
        split = sim.pass_times();
        sim.time_passes(false);
    }
    (ms, particles, split)
}

/// How the water's cost grows with the particles (issue 15): the paper scene and a 100,000 x 16
/// groom with 0 to 1,000,000 particles placed on the hair, with the paper's model and with the
/// full model. "water" is the frame less the dry frame of the same run; "x per 10x" is each
/// row's water over the row with a tenth of the particles (linear cost: at most 10). Where the
/// hair soaks drops up (the full model) a row carries fewer particles than it was given, and
/// some rows far fewer than others, so each row also gives the particles its timed frames
/// carried (mean) and its water per thousand of them. Where the hair clumps harder into denser
/// water, each particle meets more hair and the pairs grow faster than the particles; so each
/// row also gives the adhesion pairs a frame (the step's own count, read between frames at no
/// cost: `Stats::adhesion_pairs`), their growth, and the water's cost per million of them,
/// which stays flat where the cost is linear in the work.
fn particle_scaling(cores: u32, quick: bool) {
    use wethair::HeldWater;
    println!();
    println!("Cost against particles, CPU backend, {cores} threads (median ms/frame over the frames named; particles placed on the hair at the start):");
    println!();
    println!("| scene | model | particles | frames | ms/frame | water (ms over dry) | water x per 10x particles | particles carried (mean) | water per 1,000 carried, ms | adhesion pairs a frame (mean) | pairs x per 10x particles | water per million pairs, ms | particles at end |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let paper = paper_scene(10_000, 6).expect("paper scene");
    let big = paper_scene(100_000, 16).expect("big scene");
    let mut split = Vec::new();
    for (name, groom, frames) in [
        ("paper 10000x6", &paper, if quick { 10 } else { 40 }),
        ("100000x16", &big, if quick { 3 } else { 10 }),
    ] {
        let time = |model: Option<bool>, particles: usize| -> Timed {
            let mut p = SimParams {
                threads: cores,
                ..SimParams::paper_scene_with_head()
            };
            if model == Some(true) {
                p.held_water = HeldWater::ON;
            }
            p.water.capacity = p.water.capacity.max(particles as u32);
            let mut sim = Simulation::new(groom, p).expect("sim");
            if particles > 0 {
                let w = on_hair(sim.positions().as_slice(), particles, &mut Lcg(2024));
                sim.add_water(&w, &[]).expect("water");
            }
            timed_frames(&mut sim, 2, frames)
        };
        let Timed {
            ms: dry, passes: t_dry, ..
        } = time(None, 0);
        println!("| {name} | dry | 0 | {frames} | {dry:.2} | – | – | 0 | – | 0 | – | – | 0 |");
        split.push((name, "dry".to_string(), frames, t_dry));
        for (model, full) in [("paper", false), ("full", true)] {
            let (mut last, mut last_pairs): (Option<f64>, Option<f64>) = (None, None);
            for particles in [1_000usize, 10_000, 100_000, 1_000_000] {
                let Timed {
                    ms,
                    particles: held,
                    mean_particles: carried,
                    mean_pairs: pairs,
                    passes: t,
                } = time(Some(full), particles);
                let water = ms - dry;
                let ratio = |now: f64, before: Option<f64>| before.map_or("–".into(), |b| format!("{:.1}", now / b));
                let per = |of: f64, unit: f64| {
                    if of > 0.0 {
                        format!("{:.3}", water / of * unit)
                    } else {
                        "–".into()
                    }
                };
                println!(
                    "| {name} | {model} | {particles} | {frames} | {ms:.2} | {water:.2} | {} | {carried:.0} | {} | {pairs:.0} | {} | {} | {held} |",
                    ratio(water, last),
                    per(carried, 1e3),
                    ratio(pairs, last_pairs),
                    per(pairs, 1e6),
                );
                last = Some(water.max(1e-3));
                last_pairs = Some(pairs.max(1.0));
                split.push((name, format!("{model}, {particles}"), frames, t));
            }
        }
    }
    let rows: Vec<(&str, &str, usize, Vec<PassTime>)> = split
        .iter()
        .map(|(n, m, f, t)| (*n, m.as_str(), *f, t.clone()))
        .collect();
    print_pass_split(&rows);
}

/// The step's own per-pass timers for each row (ms per frame, mean over the timed frames):
/// one line per scene and model, one column per pass that ran in any.
fn print_pass_split(rows: &[(&str, &str, usize, Vec<PassTime>)]) {
    // Columns in step order: each row lists its passes in step order, so the longest first.
    let mut names: Vec<&str> = Vec::new();
    let mut by_length: Vec<_> = rows.iter().collect();
    by_length.sort_by_key(|r| std::cmp::Reverse(r.3.len()));
    for (_, _, _, t) in by_length {
        for p in t {
            if !names.contains(&p.name) {
                names.push(p.name);
            }
        }
    }
    println!();
    println!("Where the time goes (the step's own pass timers, ms per frame, mean; `blocks` is the block kernel: drag, springs, adhesion, integrate, collide, and on the CPU the bridges' pulls):");
    println!();
    println!("| scene | model | {} | sum |", names.join(" | "));
    println!("|---|---|{}---|", "---|".repeat(names.len()));
    for (scene, model, frames, t) in rows {
        let per = |n: &str| t.iter().find(|p| p.name == n).map(|p| p.ms / *frames as f64);
        let cells: Vec<String> = names
            .iter()
            .map(|n| per(n).map_or("–".into(), |ms| format!("{ms:.3}")))
            .collect();
        let sum: f64 = t.iter().map(|p| p.ms).sum::<f64>() / *frames as f64;
        println!("| {scene} | {model} | {} | {sum:.2} |", cells.join(" | "));
    }
}

/// Reading the vertices (position, tangent, wetness) against the dry step on many short
/// strands, where the copy weighs most: 48,113 x 4.
fn copy_path_cost(cores: u32, quick: bool) {
    let groom = paper_scene(48_113, 4).expect("groom");
    let mut sim = Simulation::new(&groom, SimParams::paper()).expect("sim");
    let mut v = vec![0.0f32; sim.vertex_count() * sim.attributes().stride()];
    // The floor of any copy path: the same bytes copied from a buffer already in host order.
    let src = vec![1.0f32; v.len()];
    let frames = if quick { 30 } else { 200 };
    let (mut step, mut copy, mut floor) = (Vec::new(), Vec::new(), Vec::new());
    for f in 0..frames + 5 {
        let t0 = Instant::now();
        sim.step(1.0 / 60.0).expect("step");
        let t1 = Instant::now();
        sim.write_vertices(&mut v).expect("vertices");
        let t2 = Instant::now();
        v.copy_from_slice(std::hint::black_box(&src));
        let t3 = Instant::now();
        std::hint::black_box(&v);
        if f >= 5 {
            step.push((t1 - t0).as_secs_f64() * 1e3);
            copy.push((t2 - t1).as_secs_f64() * 1e3);
            floor.push((t3 - t2).as_secs_f64() * 1e3);
        }
    }
    let (s, c, m) = (median(step), median(copy), median(floor));
    println!();
    println!("Copy path, paper scene 48113x4, {cores} threads, median of {frames} frames:");
    println!();
    println!("| dry step ms | vertex read (position, tangent, wetness) ms | read / step | memcpy of the same {:.1} MB ms (one thread) | memcpy / step |", (v.len() * 4) as f64 / 1e6);
    println!("|---|---|---|---|---|");
    println!("| {s:.3} | {c:.3} | {:.2} | {m:.3} | {:.2} |", c / s, m / s);
}

/// The cost of each integrator against symplectic Euler, per groom (dry, all cores, 1 g per
/// point, the default springs): a table of ms/frame and ratios.
fn integrator_costs(cores: u32, quick: bool) {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");
    let load = |name: &str, scale: f32, up: wethair::groom::UpAxis| {
        let opt = wethair::groom::LoadOptions {
            scale,
            up_axis: up,
            // 1 g per point and every point kept, as the table has always been measured.
            point_mass: 1e-3,
            linear_density: 0.0,
            weld_length: 0.0,
            ..Default::default()
        };
        wethair::groom::load_file_with(std::path::Path::new(&format!("{data}{name}")), &opt).expect("groom")
    };
    use wethair::groom::UpAxis;
    let grooms = [
        ("paper 10000x6", paper_scene(10_000, 6).expect("paper")),
        ("paper 2000x21", paper_scene(2_000, 21).expect("paper")),
        (
            "mohawk 2228x32 (TressFX 4)",
            load("Ratboy_mohawk.tfx", 1.0, UpAxis::KEEP),
        ),
        (
            "ponytail front 876x16 (TressFX 3)",
            load("ponytail_front_top.tfx", 0.01, UpAxis::Y_TO_Z),
        ),
        (
            "ponytail back 517x16 (TressFX 3)",
            load("ponytail_back.tfx", 0.01, UpAxis::Y_TO_Z),
        ),
    ];
    let frames = if quick { 20 } else { 100 };
    println!();
    println!("Integrator cost per groom, {cores} threads, dry, median of {frames} frames (a failed step is marked):");
    println!();
    println!("| groom | symplectic Euler ms | implicit Euler ms | ratio | XPBD ms | ratio |");
    println!("|---|---|---|---|---|---|");
    for (name, groom) in &grooms {
        let row = Row {
            scene: name.to_string(),
            particles: 0,
            threads: cores,
            collider: false,
            pile_cell: 0.0,
        };
        let time = |i: Integrator| {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_with(groom, &row, i, frames, 3)));
            r.map(|t| t.0).unwrap_or(f64::NAN)
        };
        let se = time(Integrator::SYMPLECTIC_EULER);
        let ie = time(Integrator::IMPLICIT_EULER);
        let xp = time(Integrator::XPBD);
        println!(
            "| {name} | {se:.3} | {ie:.3} | {:.1}x | {xp:.3} | {:.1}x |",
            ie / se,
            xp / se
        );
    }
}
