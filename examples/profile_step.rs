//! Steps the paper scene (head collider, `particles` placed in the hair) for `frames` frames:
//! a target for `perf record` when tuning the CPU backend (`FULL=1`: with the full wet model; `BIG=1`: on 100,000 x 16;
//! `RAIN=1`: under the bench's rain; `PASSES=1`: print the step's per-pass timers; `CAP=n`:
//! room for n particles; `PREFILTER=1`: the water grid's prefilter and candidate counts at the end;
//! `GUIDES=n`: every n-th strand a guide; `VOLUME=1`: hair-hair volume; `WRITE=1`: also copy
//! the vertices to the host each frame, timed apart; `INTEGRATOR=n`: the integrator by number,
//! with `ITERATIONS=n` Newton iterations; `HASH=1`: a hash of the positions at the end; `CLUMP=1`: the clumping measures at the end;
//! `SOAK=s`: with the full model, every point soaked to saturation `s` before the first step;
//! `FAR=1`: the particles 100 m above the head, out of the hair's reach (the lock step's own cost);
//! `GPU=1`: on the GPU backend, so a GPU change is held to the same hash; `LEDGER=1`: where the
//! water is at the end, as shares of what was added, and the drops in flight and gone;
//! `PER_LENGTH=1`: eq. 2's pull and the air drag quoted per 2 cm of hair, as
//! `wethair_sim_desc_init` gives them, instead of per point; `PILES=1`: how many places the
//! drops sit at, and the pairs were each place one drop; `PILE_CELL=m`: drops in one cell of
//! that side pull as one source, `WaterParams::pile_cell`).
//! Usage: cargo run --release --example profile_step -- [particles] [threads] [frames]
use wethair::groom::paper_scene;
use wethair::scenes::{on_hair, Lcg};
use wethair::{SimParams, Simulation};

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("integer argument"))
        .collect();
    let (particles, threads, frames) = (
        a.first().copied().unwrap_or(20),
        a.get(1).copied().unwrap_or(1),
        a.get(2).copied().unwrap_or(300),
    );
    // BIG=1: the 100,000 x 16 groom of the bench's second wet row.
    let (strands, points) = if std::env::var_os("BIG").is_some() {
        (100_000, 16)
    } else {
        (10_000, 6)
    };
    let groom = paper_scene(strands, points).expect("groom");
    let mut params = SimParams {
        threads: threads as u32,
        ..if std::env::var_os("NO_COLLIDER").is_some() {
            SimParams::paper()
        } else {
            SimParams::paper_scene_with_head()
        }
    };
    if let Some(a) = std::env::var_os("ADHESION") {
        params.water.adhesion = a.to_str().and_then(|s| s.parse().ok()).expect("ADHESION=number");
    }
    // CAP=n: room for n particles (the default holds 65,536).
    if let Some(c) = std::env::var_os("PILE_CELL") {
        params.water.pile_cell = c.to_str().and_then(|s| s.parse().ok()).expect("PILE_CELL=metres");
    }
    if let Some(c) = std::env::var_os("CAP") {
        params.water.capacity = c.to_str().and_then(|s| s.parse().ok()).expect("CAP=number");
    }
    // INTEGRATOR=n: the integrator by its number (1 implicit Euler, 2 XPBD, 4 BDF2);
    // ITERATIONS=n: Newton iterations of the implicit ones.
    if let Some(n) = std::env::var_os("INTEGRATOR") {
        use wethair::Integrator as I;
        params.integrator = match n.to_str() {
            Some("1") => I::IMPLICIT_EULER,
            Some("2") => I::XPBD,
            Some("4") => I::BDF2,
            _ => panic!("INTEGRATOR=1, 2 or 4"),
        };
    }
    if let Some(n) = std::env::var_os("ITERATIONS") {
        params.solver_iterations = n.to_str().and_then(|s| s.parse().ok()).expect("ITERATIONS=number");
    }
    if std::env::var_os("PER_LENGTH").is_some() {
        params.water.adhesion_length = wethair::physics::per_length::DEFAULT_LENGTH;
        params.air_drag_length = wethair::physics::per_length::DEFAULT_LENGTH;
    }
    if std::env::var_os("FULL").is_some() {
        params.held_water = wethair::HeldWater::ON; // the full wet model
    }
    // GUIDES=n: every n-th strand simulated, the rest followers.
    if let Some(n) = std::env::var_os("GUIDES") {
        let n = n.to_str().and_then(|s| s.parse().ok()).expect("GUIDES=number");
        params.guides = wethair::Guides::every_nth(n);
    }
    if std::env::var_os("VOLUME").is_some() {
        params.volume = wethair::Volume::ON;
    }
    if std::env::var_os("GPU").is_some() {
        params.backend = wethair::Backend::GPU;
    }
    if std::env::var_os("FAR").is_some() {
        params.water.domain_radius = 1000.0; // FAR=1, below
    }
    let mut sim = Simulation::new(&groom, params).expect("sim");
    // RAIN=1: the bench's rain over the head (100 drops a frame).
    if std::env::var_os("RAIN").is_some() {
        sim.set_rain(Some(wethair::scenes::rain_over_head())).expect("rain");
    }
    // FAR=1: the particles at rest 100 m above the head (the domain grown to hold them),
    // where no hair reaches them during the run: the cost of the water's lock step alone.
    if std::env::var_os("FAR").is_some() {
        let at = vec![glam::Vec3::new(0.0, 0.0, 100.0); particles];
        sim.add_water(&at, &[]).expect("far water");
    } else if particles > 0 {
        sim.add_water(&on_hair(groom.positions(), particles, &mut Lcg(2024)), &[])
            .expect("water");
    }
    // SOAK=s: every point soaked to saturation s first (the full model: FULL=1).
    if let Some(s) = std::env::var_os("SOAK") {
        sim.soak(s.to_str().and_then(|s| s.parse().ok()).expect("SOAK=saturation"))
            .expect("soak");
    }
    // PASSES=1: print the step's own per-pass timers after the run.
    let passes = std::env::var_os("PASSES").is_some() && sim.time_passes(true);
    // WRITE=1: every host vertex copied out after each step (followers included), timed apart.
    let mut out = std::env::var_os("WRITE").map(|_| vec![0.0f32; sim.vertex_count() * sim.attributes().stride()]);
    let mut write = std::time::Duration::ZERO;
    let t0 = std::time::Instant::now();
    for _ in 0..frames {
        sim.step(1.0 / 60.0).expect("step");
        if let Some(out) = out.as_mut() {
            let t = std::time::Instant::now();
            sim.write_vertices(out).expect("vertices");
            write += t.elapsed();
        }
    }
    let ms = (t0.elapsed() - write).as_secs_f64() * 1e3 / frames as f64;
    if out.is_some() {
        println!(
            "write_vertices {:.3} ms/frame",
            write.as_secs_f64() * 1e3 / frames as f64
        );
    }
    // PREFILTER=1: how the water grid's prefilter and candidates fare on the last frame's
    // particles (hair points passed, candidates scanned, and those truly within r_max).
    if std::env::var_os("PREFILTER").is_some() {
        let w = sim.water_positions().expect("positions");
        let (x, r) = (sim.positions(), sim.params().water.r_max);
        let mut g = wethair::physics::grid::Grid::new(w.len(), r);
        g.build(&w);
        let (mut pass, mut cand, mut near) = (0, 0, 0);
        for &x in &x {
            if g.may_have_near(x, r) {
                pass += 1;
                g.for_each_candidate(x, r, |j| {
                    cand += 1;
                    near += ((w[j as usize] - x).length() <= r) as usize;
                });
            }
        }
        println!(
            "grid {:?} cell {}: {pass} of {} points pass the prefilter, {cand} candidates, {near} within r_max",
            g.dims(),
            g.cell(),
            x.len()
        );
    }
    if passes {
        for p in sim.pass_times() {
            println!("{:>16} {:8.3} ms/frame", p.name, p.ms / frames as f64);
        }
    }
    // HASH=1: a hash of every point's position bits at the end, to hold a speed-up to the
    // same results.
    if std::env::var_os("HASH").is_some() {
        let h = sim
            .positions()
            .iter()
            .flat_map(|p| p.to_array())
            .fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
                (h ^ v.to_bits() as u64).wrapping_mul(0x0100_0000_01b3)
            });
        println!("positions hash {h:016x}");
    }
    // WET=1: how many hair points hold water at the end (wetness above zero), which is what
    // the per-point wet passes can skip or not.
    if std::env::var_os("WET").is_some() {
        let a = sim.attributes();
        if let Some(o) = a.offset(wethair::VertexAttributes::WETNESS) {
            let mut v = vec![0.0f32; sim.vertex_count() * a.stride()];
            sim.write_vertices(&mut v).expect("vertices");
            let wet = v.chunks(a.stride()).filter(|p| p[o] > 0.0).count();
            println!("{wet} of {} points hold water", sim.vertex_count());
        }
    }
    // NEAR=1: how many strands have a point within r_max plus a margin of a particle at the
    // end (what a step could run apart from the particles, all substeps at once, were it
    // known in advance that no particle reaches them within the step).
    if std::env::var_os("NEAR").is_some() {
        let w = sim.water_positions().expect("positions");
        let x = sim.positions();
        let strands = strands as usize;
        let n = x.len() / strands;
        for margin in [0.0f32, 0.01, 0.02, 0.05] {
            let r = sim.params().water.r_max + margin;
            let mut g = wethair::physics::grid::Grid::new(w.len().max(1), r);
            g.build(&w);
            let near = (0..strands)
                .filter(|&s| {
                    x[s * n..(s + 1) * n].iter().any(|&p| {
                        let mut hit = false;
                        g.for_each_candidate(p, r, |j| hit |= (w[j as usize] - p).length() <= r);
                        hit
                    })
                })
                .count();
            println!("margin {margin} m: {near} of {strands} strands within r_max + margin of a particle");
        }
    }
    // PILES=1: where the drops sit at the end: how many places they occupy (bit for bit, and
    // in cells of 0.1, 0.5 and 1 mm, a cell's drops counted once at their mean), how many
    // sit at the place of the drop before them in the grid's order, and the hair points
    // within r_max summed over drops, over places, and over each cell size's places: what
    // the pairs would be were the drops at one place one drop.
    if std::env::var_os("PILES").is_some() {
        let w = sim.water_positions().expect("positions");
        let (x, r) = (sim.positions(), sim.params().water.r_max);
        let mut g = wethair::physics::grid::Grid::new(x.len(), r);
        g.build(&x);
        let pairs = |q: &[glam::Vec3]| -> usize {
            let mut n = 0;
            for &p in q {
                g.for_each_candidate(p, r, |i| n += ((x[i as usize] - p).length() <= r) as usize);
            }
            n
        };
        let bits = |p: &glam::Vec3| p.to_array().map(f32::to_bits);
        let next = w.windows(2).filter(|p| bits(&p[0]) == bits(&p[1])).count();
        let places: std::collections::BTreeSet<[u32; 3]> = w.iter().map(bits).collect();
        let places: Vec<glam::Vec3> = places
            .iter()
            .map(|b| glam::Vec3::from_array(b.map(f32::from_bits)))
            .collect();
        print!(
            "piles: {} drops at {} places ({} beside their pile's last in grid order); pairs: {} by drop, {} by place",
            w.len(),
            places.len(),
            next,
            pairs(&w),
            pairs(&places)
        );
        for cell in [1.0e-4f32, 5.0e-4, 1.0e-3] {
            let mut sums = std::collections::BTreeMap::<[i32; 3], (glam::Vec3, f32)>::new();
            for &p in &w {
                let e = sums.entry((p / cell).floor().as_ivec3().to_array()).or_default();
                *e = (e.0 + p, e.1 + 1.0);
            }
            let means: Vec<glam::Vec3> = sums.values().map(|&(s, n)| s / n).collect();
            print!(
                "; {:.1} mm cells: {} places, {} pairs",
                cell * 1e3,
                means.len(),
                pairs(&means)
            );
        }
        println!();
    }
    // CLUMP=1: the clumping measures at the end (tips, and along the strands), m.
    if std::env::var_os("CLUMP").is_some() {
        let st = sim.stats();
        println!(
            "clumping {:.6} m at the tips, {:.6} m along the strands",
            st.clumping, st.clumping_along
        );
    }
    // LEDGER=1: where the water is at the end (full model), as shares of what was added; the
    // drops in flight, those gone out of the domain, and the last step's adhesion pairs.
    if std::env::var_os("LEDGER").is_some() {
        if let Some(l) = sim.water_ledger() {
            let share = |q: u64| 100.0 * q as f64 / l.added.max(1) as f64;
            let st = sim.stats();
            println!(
                "water: {:.2} % held, {:.2} % in particles, {:.2} % left, {:.2} % evaporated; {} drops in flight, {} gone, {} adhesion pairs in the last step",
                share(l.held),
                share(l.in_particles),
                share(l.left),
                share(l.evaporated),
                st.particles,
                st.particles_removed,
                st.adhesion_pairs
            );
        }
    }
    println!("{:.3} ms/frame, {} particles held", ms, sim.stats().particles);
}
