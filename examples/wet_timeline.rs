//! The wet model over time on the paper scene, as in the main job's strip: a shower of 1,000
//! drops from 0.5 s (or, with `shower` 0, the hair soaked to 1.5 times its hold limit at 0.5 s
//! instead; with `shower` < 0, both), then nothing but the hair's own water, drying with time
//! constant `tau`. The paper scene's points weigh 1 g (a wisp of thousands of hairs), so the
//! hair takes a thirtieth of the default capacity and a fiftieth of the default water between
//! fibres, and sheds 30 mg drops (see examples/c/render.c).
//! Prints one CSV row per tenth of a second: time, water in particles / held / left /
//! evaporated (g), the along-strand clumping of the wet run and of a dry twin (mm), their
//! ratio; `--svg FILE` also draws held water and the clumping ratio against time.
//!
//!     cargo run --release --example wet_timeline -- [strands] [seconds] [shower] [tau] [kappa] [--svg FILE]
//!
//! (`kappa`: the liquid bridges' pull per metre, N/m; 0 switches them off.)

#[path = "report/svg.rs"]
#[allow(dead_code)] // the report's log-log plots and maps are not drawn here
mod svg;

use wethair::groom::paper_scene;
use wethair::physics::wet::WATER_QUANTUM;
use wethair::scenes::{shower, Lcg};
use wethair::{Backend, HeldWater, SimParams, Simulation};

fn main() {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let svg_path = all
        .iter()
        .position(|a| a == "--svg")
        .and_then(|i| all.get(i + 1))
        .cloned();
    let args: Vec<f32> = all.iter().filter_map(|a| a.parse().ok()).collect();
    let strands = args.first().map_or(10_000, |&v| v as u32);
    let seconds = args.get(1).copied().unwrap_or(10.0);
    let shower_mode = args.get(2).copied().unwrap_or(-1.0);
    let tau = args.get(3).copied().unwrap_or(1.0);
    let kappa = args.get(4).copied().unwrap_or(HeldWater::ON.bridge_tension);
    let groom = paper_scene(strands, 6).unwrap();
    let base = SimParams {
        backend: Backend::CPU,
        ..SimParams::paper_scene_with_head()
    };
    let wet_params = SimParams {
        held_water: HeldWater {
            dry_time: tau,
            bridge_tension: kappa,
            capacity_ratio: 0.01,
            free_ratio: 0.02,
            drip_mass: 3.0e-5,
            ..HeldWater::ON
        },
        ..base.clone()
    };
    let mut wet = Simulation::new(&groom, wet_params).unwrap();
    let mut dry = Simulation::new(&groom, base).unwrap();
    let dt = 1.0 / 60.0;
    let mut rng = Lcg(7);
    let g = |q: u64| q as f64 * WATER_QUANTUM * 1e3;
    println!("t_s,particles_g,held_g,left_g,evaporated_g,clumping_wet_mm,clumping_dry_mm,ratio");
    let (mut held, mut ratio) = (Vec::new(), Vec::new());
    let (soak_at, soaks, showers) = (0.5f32, shower_mode <= 0.0, shower_mode != 0.0);
    let (mut soaked, mut sprayed) = (false, 0);
    let frames = (seconds / dt).round() as usize;
    for f in 0..frames {
        if f as f32 * dt >= soak_at {
            if soaks && !soaked {
                wet.soak(1.5).unwrap();
                soaked = true;
            }
            if showers && sprayed < 1000 {
                let (p, v) = shower(50, &mut rng);
                wet.add_water(&p, &v).unwrap();
                sprayed += 50;
            }
        }
        wet.step(dt).unwrap();
        dry.step(dt).unwrap();
        if (f + 1) % 6 == 0 {
            let l = wet.water_ledger().unwrap();
            let (cw, cd) = (wet.stats().clumping_along * 1e3, dry.stats().clumping_along * 1e3);
            let t = (f + 1) as f32 * dt;
            println!(
                "{t:.2},{:.3},{:.3},{:.3},{:.3},{cw:.3},{cd:.3},{:.3}",
                g(l.in_particles),
                g(l.held),
                g(l.left),
                g(l.evaporated),
                cw / cd
            );
            held.push((t as f64, g(l.held)));
            ratio.push((t as f64, (cw / cd) as f64));
        }
    }
    if let Some(path) = svg_path {
        let mut body = String::new();
        let panel = |ox: f64, title: &'static str, yl: &'static str| svg::Panel {
            ox,
            oy: 0.0,
            w: 420.0,
            h: 300.0,
            title,
            xl: "time, s",
            yl,
        };
        let series = |label: &str, colour, points| svg::Series {
            label: label.into(),
            colour,
            points,
        };
        let held_panel = panel(0.0, "Water held by the hair", "held water, g");
        svg::linear(&mut body, &held_panel, &[series("held", svg::COLOURS[0], held)]);
        let ratio_panel = panel(420.0, "Clumping, wet over dry (1: as dry)", "clumping ratio");
        svg::linear(&mut body, &ratio_panel, &[series("wet / dry", svg::COLOURS[1], ratio)]);
        std::fs::write(&path, svg::document(840.0, 300.0, &body)).expect("write the plot");
        eprintln!("wrote {path}");
    }
}
