//! The paper scene (10,000 x 6... here 1,000 x 16) on the CPU, the GPU, and the CPU with its
//! water nudged by 1e-7 m: how far the GPU is from the CPU next to how far the CPU is from
//! itself (the chaos floor). `cargo run --release --example gpu_probe`; tests assert parity.
//! `-- dry`: the dry paper scene (10,000 x 6), the third simulation's head moved by 1e-7 m.
use wethair::{groom::paper_scene, Backend, SimParams, Simulation};

fn main() {
    let dry = std::env::args().any(|a| a == "dry");
    let groom = if dry {
        paper_scene(10_000, 6)
    } else {
        paper_scene(1000, 16)
    }
    .expect("paper scene");
    let mut sims: Vec<Simulation> = [Backend::CPU, Backend::GPU, Backend::CPU]
        .iter()
        .map(|&b| {
            Simulation::new(
                &groom,
                SimParams {
                    backend: b,
                    ..SimParams::paper_scene_with_head()
                },
            )
            .expect("create")
        })
        .collect();
    println!("{:?}", sims[1].backend_info());
    let water = wethair::scenes::on_hair(&sims[0].positions(), 1000, &mut wethair::scenes::Lcg(3));
    if dry {
        let nudge = glam::Mat4::from_translation(glam::Vec3::splat(1e-7));
        sims[2].set_head_transform(nudge).expect("head");
    }
    for f in 0..100 {
        if f == 10 && !dry {
            for (k, sim) in sims.iter_mut().enumerate() {
                // The third simulation gets water nudged by 1e-7 m: the CPU against itself.
                let w: Vec<_> = water
                    .iter()
                    .map(|p| if k == 2 { *p + glam::Vec3::splat(1e-7) } else { *p })
                    .collect();
                sim.add_water(&w, &[]).expect("water");
            }
        }
        for sim in &mut sims {
            sim.step(1.0 / 60.0).expect("step");
        }
        if f % 20 == 19 {
            let (a, b) = (sims[0].positions(), sims[1].positions());
            let d = a.iter().zip(&b).map(|(p, q)| (*p - *q).length()).fold(0.0, f32::max);
            let c = sims[2].positions();
            let d2 = a.iter().zip(&c).map(|(p, q)| (*p - *q).length()).fold(0.0, f32::max);
            let (sa, sb) = (sims[0].stats(), sims[1].stats());
            println!(
                "frame {f}: max |dx| gpu {d:.3e} m, cpu nudged {d2:.3e} m, particles {} / {}, clumping {:.5} / {:.5}",
                sa.particles, sb.particles, sa.clumping, sb.clumping
            );
        }
    }
    println!("{:?}", sims[1].gpu_dispatches());
}
