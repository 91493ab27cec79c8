//! Ready-made inputs shared by the examples, benchmarks and tests: the water spray over the
//! paper scene's head, and placements of particles on hair.

use glam::Vec3;

/// A small deterministic generator (LCG), so every front end sprays the same water.
#[derive(Clone, Debug)]
pub struct Lcg(pub u32);

impl Lcg {
    /// Next value in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (self.0 >> 8) as f32 / (1u32 << 24) as f32
    }
}

/// `count` particles in a disc of radius 0.16 m at height 0.3 m above the paper scene's head,
/// falling at 1 m/s: a shower. Returns positions and velocities.
pub fn shower(count: usize, rng: &mut Lcg) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut pos = Vec::with_capacity(count);
    for _ in 0..count {
        let r = 0.16 * rng.next_f32().sqrt();
        let th = rng.next_f32() * std::f32::consts::TAU;
        pos.push(Vec3::new(r * th.cos(), r * th.sin(), 0.3));
    }
    (pos, vec![Vec3::new(0.0, 0.0, -1.0); count])
}

/// `count` particles at rest, each placed 1 mm off a hair point chosen at random: water already
/// in the hair (the paper's scattered particles). Used by the benchmark's wet rows.
pub fn on_hair(hair: &[Vec3], count: usize, rng: &mut Lcg) -> Vec<Vec3> {
    (0..count)
        .map(|_| {
            let i = ((rng.next_f32() * hair.len() as f32) as usize).min(hair.len() - 1);
            let jitter = Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, rng.next_f32() - 0.5);
            hair[i] + jitter * 0.002
        })
        .collect()
}
