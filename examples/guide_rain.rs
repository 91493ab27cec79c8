//! How many of the paper model's drops stay in the hair with every strand simulated and with
//! a tenth (guides, every 10th strand), on the paper scene's 10,000 strands under gravity:
//! 1,000 drops of the paper's gram placed on the hair (on the hair as it hangs after
//! `settle` seconds when that is above 0), then counted every half second. A guide pulls a
//! drop back with its bundle's hair (docs/GUIDES.md "Water"); the drops are placed on the
//! simulated strands' points, so that both runs start with every drop within reach.
//!
//!     cargo run --release --example guide_rain -- [seconds] [settle] [cpu|gpu]

use wethair::groom::paper_scene;
use wethair::scenes::{on_hair, Lcg};
use wethair::{Backend, Guides, SimParams, Simulation};

const DT: f32 = 1.0 / 60.0;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seconds: f32 = args.first().map_or(2.0, |s| s.parse().expect("seconds"));
    let settle: f32 = args.get(1).map_or(0.0, |s| s.parse().expect("settle seconds"));
    let backend = match args.get(2).map(String::as_str) {
        Some("gpu") => Backend::GPU,
        _ => Backend::CPU,
    };
    let groom = paper_scene(10_000, 6).expect("the paper scene");
    let frames = (seconds / DT).round() as usize;
    let mut kept: Vec<Vec<usize>> = Vec::new();
    for guides in [Guides::ALL, Guides::every_nth(10)] {
        let p = SimParams {
            backend,
            guides,
            ..SimParams::paper()
        };
        let mut sim = Simulation::new(&groom, p).expect("a simulation");
        for _ in 0..(settle / DT).round() as usize {
            sim.step(DT).expect("a dry step");
        }
        // The simulated points as they hang now: every strand's, or the guides'.
        let hair = sim.positions();
        sim.add_water(&on_hair(&hair, 1000, &mut Lcg(2024)), &[])
            .expect("the drops");
        let mut counts = Vec::new();
        for f in 1..=frames {
            sim.step(DT).expect("a wet step");
            if f % 30 == 0 {
                counts.push(sim.stats().particles as usize);
            }
        }
        kept.push(counts);
    }
    println!("seconds,drops kept (every strand),drops kept (a tenth simulated)");
    for (k, (a, t)) in kept[0].iter().zip(&kept[1]).enumerate() {
        println!("{:.1},{a},{t}", 0.5 * (k + 1) as f32);
    }
}
