//! The wet model over time on the paper scene: a shower for `shower` seconds (0: the hair is
//! soaked to saturation at the start instead), then nothing but the hair's own water, drying
//! with time constant `tau`. Prints one CSV row per tenth of a
//! second: time, water in particles / held / left / evaporated (g), the along-strand clumping
//! of the wet run and of a dry twin (mm), and their ratio.
//!
//!     cargo run --release --example wet_timeline -- [strands] [seconds] [shower] [tau] [kappa]
//!
//! (`kappa`: the liquid bridges' pull per metre, N/m; 0 switches them off.)

use wethair::groom::paper_scene;
use wethair::physics::wet::WATER_QUANTUM;
use wethair::scenes::{shower, Lcg};
use wethair::{Backend, HeldWater, SimParams, Simulation};

fn main() {
    let args: Vec<f32> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let strands = args.first().map_or(10_000, |&v| v as u32);
    let seconds = args.get(1).copied().unwrap_or(6.0);
    let shower_s = args.get(2).copied().unwrap_or(1.0);
    let tau = args.get(3).copied().unwrap_or(2.0);
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
            ..HeldWater::ON
        },
        ..base.clone()
    };
    let mut wet = Simulation::new(&groom, wet_params).unwrap();
    let mut dry = Simulation::new(&groom, base).unwrap();
    let dt = 1.0 / 60.0;
    if shower_s <= 0.0 {
        wet.soak(1.0).unwrap();
    }
    let mut rng = Lcg(7);
    let g = |q: u64| q as f64 * WATER_QUANTUM * 1e3;
    println!("t_s,particles_g,held_g,left_g,evaporated_g,clumping_wet_mm,clumping_dry_mm,ratio");
    let frames = (seconds / dt).round() as usize;
    for f in 0..frames {
        let t = f as f32 * dt;
        if t < shower_s {
            let (p, v) = shower(20, &mut rng);
            wet.add_water(&p, &v).unwrap();
        }
        wet.step(dt).unwrap();
        dry.step(dt).unwrap();
        if (f + 1) % 6 == 0 {
            let l = wet.water_ledger().unwrap();
            let (cw, cd) = (wet.stats().clumping_along * 1e3, dry.stats().clumping_along * 1e3);
            println!(
                "{:.2},{:.3},{:.3},{:.3},{:.3},{cw:.3},{cd:.3},{:.3}",
                (f + 1) as f32 * dt,
                g(l.in_particles),
                g(l.held),
                g(l.left),
                g(l.evaporated),
                cw / cd
            );
        }
    }
}
