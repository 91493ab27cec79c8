//! GPU and CPU backends side by side, one run: ms/frame on the paper scene (10,000 × 6, head
//! collider) dry and with 1,000 particles, and on a large scene (100,000 × 32, 100,000
//! particles), with the paper's model, with it and drops that meet coalescing in 0.1 mm cells
//! (`WaterParams::pile_cell`), and with the full wet model (held water with liquid bridges,
//! absorption, flow, drip and drying). Every row names its device.
//!
//! A GPU step returns once submitted, so a row times `frames` steps and one blocking vertex
//! read at the end (which waits for all of them) and divides by `frames`: throughput, the
//! figure a host that reads every frame one frame late sees. CPU rows time the same way.
//! Where the adapter has timestamp queries, a second column gives the GPU time of the step's
//! compute pass (median of up to 20 steps, each read back before the next). A second table
//! splits each row's step by stage over up to 20 more steps (`Simulation::time_passes`: GPU
//! timestamps after each stage where the adapter writes them inside a pass, wall time on the
//! CPU), under the same stage names on both backends.
//!
//! Run: `cargo bench --bench backends` (`-- --quick` for fewer frames, `-- --only "large
//! 100000 "` for the rows whose scene, particle count and model read so, `-- --gpu` for the
//! GPU rows alone). Without a GPU adapter
//! the GPU rows say so. The GPU rows add the particles' reactions by atomics unless
//! `WETHAIR_GPU_REACTIONS=gather` is set (the particles gather them; the same bits), and the
//! header says which: run it both ways to compare the forms on one device.

use std::time::Instant;
use wethair::groom::{paper_scene, Groom};
use wethair::scenes::{on_hair, Lcg};
use wethair::{Backend, HeldWater, Integrator, SimParams, Simulation};

/// The water's model in a row.
#[derive(Clone, Copy, PartialEq)]
enum Model {
    /// The paper's.
    Paper,
    /// The paper's, with drops that meet coalescing in 0.1 mm cells.
    Piles,
    /// The full wet model.
    Full,
}

impl Model {
    fn name(self) -> &'static str {
        match self {
            Model::Paper => "paper",
            Model::Piles => "paper, coalescing",
            Model::Full => "full wet model",
        }
    }
}

/// What one row measured.
struct Measured {
    /// ms/frame, throughput.
    ms: f64,
    /// Median GPU ms per step from timestamps, or "-".
    gpu_ms: String,
    device: String,
    /// Dispatches (GPU) or passes (CPU) per step.
    what: String,
    /// ms per step by stage, or "-" where the backend cannot time its stages.
    split: String,
}

/// One row's figures, or the reason there is no row.
fn run(
    groom: &Groom,
    backend: Backend,
    integrator: Integrator,
    particles: usize,
    model: Model,
    frames: usize,
) -> Result<Measured, String> {
    let mut params = SimParams {
        backend,
        integrator,
        ..SimParams::paper_scene_with_head()
    };
    match model {
        Model::Paper => {}
        Model::Piles => params.water.pile_cell = 1.0e-4,
        Model::Full => params.held_water = HeldWater::ON,
    }
    params.water.capacity = params.water.capacity.max(particles as u32);
    let mut sim = Simulation::new(groom, params).map_err(|e| e.to_string())?;
    if particles > 0 {
        let water = on_hair(groom.positions(), particles, &mut Lcg(2024));
        sim.add_water(&water, &[]).map_err(|e| e.to_string())?;
    }
    let mut v = vec![0.0f32; sim.vertex_count() * sim.attributes().stride()];
    for _ in 0..3 {
        sim.step(1.0 / 60.0).map_err(|e| e.to_string())?;
    }
    sim.write_vertices(&mut v).map_err(|e| e.to_string())?;
    let t0 = Instant::now();
    for _ in 0..frames {
        sim.step(1.0 / 60.0).map_err(|e| e.to_string())?;
    }
    sim.write_vertices(&mut v).map_err(|e| e.to_string())?;
    let ms = t0.elapsed().as_secs_f64() * 1e3 / frames as f64;
    // GPU time per step from timestamp queries, where the adapter has them: a separate,
    // synchronised pass over a few frames (reading a timestamp waits for the step).
    let gpu_ms = if sim.enable_gpu_timing() {
        let mut t = Vec::new();
        for _ in 0..frames.min(20) {
            sim.step(1.0 / 60.0).map_err(|e| e.to_string())?;
            if let Some(r) = sim.last_step_gpu_ms() {
                t.push(r.map_err(|e| e.to_string())?);
            }
        }
        t.sort_by(|a, b| a.total_cmp(b));
        t.get(t.len() / 2).map_or("-".into(), |m| format!("{m:.2}"))
    } else {
        "-".into()
    };
    // Where a step's time goes, stage by stage (each timed GPU step waits for its stamps).
    let split = if sim.time_passes(true) {
        let steps = frames.min(20);
        for _ in 0..steps {
            sim.step(1.0 / 60.0).map_err(|e| e.to_string())?;
        }
        let times = sim.pass_times();
        sim.time_passes(false);
        let parts: Vec<String> = times
            .iter()
            .map(|p| format!("{} {:.3}", p.name, p.ms / steps as f64))
            .collect();
        let sum: f64 = times.iter().map(|p| p.ms).sum::<f64>() / steps as f64;
        format!("{} (sum {sum:.3})", parts.join(" · "))
    } else {
        "-".into()
    };
    let passes: Vec<&str> = sim.gpu_dispatches();
    let what = if passes.is_empty() {
        sim.passes().iter().map(|p| p.name()).collect::<Vec<_>>().join(" ")
    } else {
        passes.join(" ")
    };
    Ok(Measured {
        ms,
        gpu_ms,
        device: sim.backend_info().device.clone(),
        what,
        split,
    })
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    // `--gpu`: the GPU rows alone.
    let gpu_only = std::env::args().any(|a| a == "--gpu");
    // `--only TEXT`: the rows whose "scene particles model" contains TEXT.
    let args: Vec<String> = std::env::args().collect();
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let (paper_frames, big_frames) = if quick { (20, 2) } else { (100, 5) };
    let paper = paper_scene(10_000, 6).expect("paper scene");
    let big = paper_scene(100_000, 32).expect("large scene");
    println!(
        "wethair {} backends; frame = 1/60 s in 4 substeps; ms/frame = (frames + final read) / frames",
        env!("CARGO_PKG_VERSION")
    );
    #[cfg(feature = "gpu")]
    let gathered = wethair::gpu::device::gathers_reactions();
    #[cfg(not(feature = "gpu"))]
    let gathered = false;
    println!(
        "GPU reactions: {}",
        if gathered {
            "gathered by the particles (WETHAIR_GPU_REACTIONS=gather)"
        } else {
            "added by the hair points' atomics (the default; WETHAIR_GPU_REACTIONS=gather gathers them)"
        }
    );
    println!();
    println!(
        "| scene | water particles | model | integrator | backend | device | ms/frame | GPU timestamps ms/step (median) | frames | dispatches (GPU) or passes (CPU) per step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let se = Integrator::SYMPLECTIC_EULER;
    // The large scene dry, with a little water and with the target's 100,000 particles, so
    // the rows say what the hair costs and what the water adds; then the GPU alone from
    // 10,000 to 1,000,000 particles (the CPU's sweep is `frame -- particles`), so the rows say
    // how the water's cost grows.
    // (scene, groom, integrator, particles, model, frames, with the CPU)
    let (paper_m, piles, full) = (Model::Paper, Model::Piles, Model::Full);
    let rows: [(&str, &Groom, Integrator, usize, Model, usize, bool); 17] = [
        ("paper 10000x6", &paper, se, 0, paper_m, paper_frames, true),
        ("paper 10000x6", &paper, se, 1000, paper_m, paper_frames, true),
        ("paper 10000x6", &paper, se, 1000, piles, paper_frames, true),
        ("paper 10000x6", &paper, se, 1000, full, paper_frames, true),
        (
            "paper 10000x6",
            &paper,
            Integrator::IMPLICIT_EULER,
            0,
            paper_m,
            paper_frames,
            true,
        ),
        ("paper 10000x6", &paper, se, 10_000, paper_m, paper_frames, false),
        ("paper 10000x6", &paper, se, 100_000, paper_m, paper_frames, false),
        ("large 100000x32", &big, se, 0, paper_m, big_frames, true),
        ("large 100000x32", &big, se, 1000, paper_m, big_frames, true),
        ("large 100000x32", &big, se, 1000, piles, big_frames, false),
        ("large 100000x32", &big, se, 10_000, paper_m, big_frames, false),
        ("large 100000x32", &big, se, 100_000, paper_m, big_frames, true),
        ("large 100000x32", &big, se, 100_000, piles, big_frames, false),
        ("large 100000x32", &big, se, 100_000, full, big_frames, true),
        ("large 100000x32", &big, se, 1_000_000, paper_m, big_frames, false),
        ("large 100000x32", &big, se, 1_000_000, piles, big_frames, false),
        ("large 100000x32", &big, se, 1_000_000, full, big_frames, false),
    ];
    let mut splits = Vec::new();
    for (name, groom, integrator, particles, model_kind, frames, with_cpu) in rows {
        let model = model_kind.name();
        if only
            .as_ref()
            .is_some_and(|o| !format!("{name} {particles} {model}").contains(o.as_str()))
        {
            continue;
        }
        let backends: &[Backend] = if with_cpu && !gpu_only {
            &[Backend::GPU, Backend::CPU]
        } else {
            &[Backend::GPU]
        };
        for &backend in backends {
            let i = format!("{integrator:?}");
            match run(groom, backend, integrator, particles, model_kind, frames) {
                Ok(m) => {
                    let (ms, gpu_ms, device, what) = (m.ms, &m.gpu_ms, &m.device, &m.what);
                    println!(
                        "| {name} | {particles} | {model} | {i} | {backend:?} | {device} | {ms:.2} | {gpu_ms} | {frames} | {what} |"
                    );
                    splits.push(format!(
                        "| {name} | {particles} | {model} | {i} | {backend:?} | {} |",
                        m.split
                    ));
                }
                Err(e) => {
                    println!("| {name} | {particles} | {model} | {i} | {backend:?} | none: {e} | - | - | - | - |")
                }
            }
        }
    }
    println!();
    println!("Where a step's time goes: ms per step by stage (GPU: timestamps; CPU: wall time), up to 20 steps");
    println!();
    println!("| scene | water particles | model | integrator | backend | stages, ms/step |");
    println!("|---|---|---|---|---|---|");
    for s in splits {
        println!("{s}");
    }
}
