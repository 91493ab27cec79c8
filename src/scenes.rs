//! Ready-made inputs shared by the examples, benchmarks and tests: the water spray over the
//! paper scene's head, rain over it, and placements of particles on hair.

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

/// Rain over the paper scene's head (half a metre square at 0.6 m, 6,000 drops a second:
/// 100 a frame at 60 Hz, falling at 2 m/s): the benchmark's wet rain row.
pub fn rain_over_head() -> crate::Rain {
    crate::Rain {
        center: Vec3::new(0.0, 0.0, 0.6),
        size: [0.5, 0.5],
        rate: 6000.0,
        speed: 2.0,
        seed: 1,
    }
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

/// The scenes of the work-precision report: a name, a groom, parameters and water.
pub struct ReportScene {
    /// Short name (file names, legends).
    pub name: &'static str,
    /// The strands.
    pub groom: crate::groom::Groom,
    /// Their parameters (no collider: the reference has none).
    pub params: crate::SimParams,
    /// Water particles, at rest, added at t = 0.
    pub water: Vec<Vec3>,
    /// Saturation every hair point is soaked to at t = 0 (`Simulation::soak`; 0: dry). Only
    /// with `params.held_water` on.
    pub soak: f32,
}

impl ReportScene {
    /// A simulation of the scene at t = 0 with `params` (the scene's, changed as the caller
    /// likes): water added, hair soaked.
    pub fn simulation(&self, params: crate::SimParams) -> crate::Result<crate::Simulation> {
        let mut sim = crate::Simulation::new(&self.groom, params)?;
        if !self.water.is_empty() {
            sim.add_water(&self.water, &[])?;
        }
        if self.soak > 0.0 {
            sim.soak(self.soak)?;
        }
        Ok(sim)
    }

    /// The f64 reference of the scene at t = 0 (soaked as the scene is).
    pub fn reference(&self) -> crate::reference::Reference {
        let r = crate::reference::Reference::new(&self.groom, &self.params, &self.water);
        if self.soak > 0.0 {
            r.soaked(self.soak as f64, &self.params.held_water)
        } else {
            r
        }
    }
}

/// One strand of 10 points released horizontally from a pinned root: a swinging chain.
pub fn swinging_chain() -> ReportScene {
    let pos: Vec<Vec3> = (0..10).map(|i| Vec3::new(0.02 * i as f32, 0.0, 0.0)).collect();
    let groom = crate::groom::Groom::new(pos, &[10], None, None, 1e-3).expect("valid chain");
    ReportScene {
        name: "swinging_chain",
        groom,
        params: crate::SimParams::paper(),
        water: vec![],
        soak: 0.0,
    }
}

/// The swinging chain soaked: every point holds twice its dry mass of water (a wisp holding
/// water between its fibres as well as in them), held still (no flow, drip, drying or
/// absorption), with the default limpness: the wet model's weight and limp bending, the one
/// wet case where pointwise error means something (no particles, no chaos).
pub fn soaked_chain() -> ReportScene {
    let mut sc = swinging_chain();
    sc.name = "soaked_chain";
    sc.params.held_water = crate::HeldWater {
        capacity_ratio: 2.0,
        free_ratio: 0.0,
        dry_time: 0.0,
        absorb_rate: 0.0,
        bridge_tension: 0.0,
        flow_mobility: 0.0,
        ..crate::HeldWater::ON
    };
    sc.soak = 1.0;
    sc
}

/// A patch of the paper scene: the `strands` strands whose roots are nearest the side of the
/// head at 20 degrees above the equator, with `particles` water particles placed in the hair:
/// clumping in a small scene. (Not the crown: strands there point straight up, an unstable
/// equilibrium whose buckling amplifies any difference exponentially, which no reference can
/// resolve at 1 s.) `stiffness` scales both spring families.
pub fn paper_slice(strands: usize, particles: usize, stiffness: f32) -> ReportScene {
    let full = crate::groom::paper_scene(10_000, 6).expect("paper scene");
    let centre = Vec3::new(1.0, 0.0, 0.36).normalize();
    let mut order: Vec<usize> = (0..full.strand_count()).collect();
    let key = |s: usize| -full.positions()[s * 6].normalize().dot(centre);
    order.sort_by(|&a, &b| key(a).total_cmp(&key(b)));
    let pos: Vec<Vec3> = order[..strands]
        .iter()
        .flat_map(|&s| full.positions()[s * 6..s * 6 + 6].to_vec())
        .collect();
    let groom = crate::groom::Groom::new(pos, &vec![6; strands], None, None, 1e-3).expect("slice");
    // Air drag makes the wet scene dissipative: undamped, particles rattling among strands make
    // it chaotic, and no reference can be trusted at 1 s (see the report).
    let mut params = crate::SimParams {
        air_drag: 0.05,
        ..crate::SimParams::paper()
    };
    params.stretch.stiffness *= stiffness;
    params.bend.stiffness *= stiffness;
    let water = on_hair(groom.positions(), particles, &mut Lcg(77));
    let name = match (particles, stiffness == 1.0) {
        (0, true) => "paper_slice_dry",
        (0, false) => "paper_slice_dry_stiff",
        (_, true) => "paper_slice_wet",
        (_, false) => "paper_slice_wet_stiff",
    };
    ReportScene {
        name,
        groom,
        params,
        water,
        soak: 0.0,
    }
}
