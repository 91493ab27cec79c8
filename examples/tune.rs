//! Scratch: clumping with sprayed water (tuning aid).
use glam::Vec3;
use wethair::{groom::paper_scene, SimParams, Simulation};

fn main() {
    let a: Vec<f32> = std::env::args().skip(1).map(|s| s.parse().unwrap()).collect();
    let groom = paper_scene(10_000, 6).unwrap();
    let mut p = SimParams::paper_scene_with_head();
    if a.len() >= 4 {
        p.water.r_min = a[0];
        p.water.r_max = a[1];
        p.water.adhesion = a[2];
        p.water.particle_mass = a[3];
    }
    let mut dry = Simulation::new(&groom, p.clone()).unwrap();
    let mut wet = Simulation::new(&groom, p).unwrap();
    let mut seed = 12345u32;
    let mut rnd = || {
        seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let t0 = std::time::Instant::now();
    for f in 0..200 {
        if f < 20 {
            let mut pos = vec![];
            let mut vel = vec![];
            for _ in 0..50 {
                let r = 0.16 * rnd().sqrt();
                let th = rnd() * 6.2831853;
                pos.push(Vec3::new(r * th.cos(), r * th.sin(), 0.3));
                vel.push(Vec3::new(0.0, 0.0, -1.0));
            }
            wet.add_water(&pos, &vel).unwrap();
        }
        dry.step(1.0 / 60.0).unwrap();
        wet.step(1.0 / 60.0).unwrap();
        if f % 40 == 39 {
            let (d, w) = (dry.stats(), wet.stats());
            println!("frame {f}: dry {:.5} wet {:.5} ratio {:.3} particles {} removed {} maxv {:.2} wet ms {:.3}", d.clumping, w.clumping, w.clumping / d.clumping, w.particles, w.particles_removed, w.max_speed, w.last_step_ms);
        }
    }
    println!("total {:?}", t0.elapsed());
    count(&wet);
}

#[allow(dead_code)]
pub fn count(sim: &Simulation) {
    let w = sim.water_positions();
    let mut g = wethair::physics::grid::Grid::new(w.len(), 2.0 * sim.params().water.r_max);
    g.build(w);
    let (mut cand, mut near, mut queried) = (0usize, 0usize, 0usize);
    let r = sim.params().water.r_max;
    for x in sim.positions() {
        let mut any = false;
        g.for_each_candidate(x, r, |j| {
            any = true;
            cand += 1;
            if (w[j as usize] - x).length() <= r {
                near += 1
            }
        });
        queried += any as usize;
    }
    println!("grid dims {:?} cell {}: points with candidates {queried}, candidates {cand}, near pairs {near}", g.dims(), g.cell());
}
