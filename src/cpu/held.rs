//! Held water on the CPU backend (docs/WET_MODEL.md §1, §3, §7): each point's water in whole
//! quanta, its capacity, the row parameters with each free point's inverse mass taken from its
//! dry mass plus its water, the drying pass, and the ledger. Exists only when the scene has
//! held water switched on.

use super::layout::{Layout, ParamRow, StateRow};
use crate::engine::WaterLedger;
use crate::params::HeldWater;
use crate::physics::lanes::{Lane, W};
use crate::physics::wet;

/// The held water of every point, per row of 8 lanes.
#[derive(Debug)]
pub struct Held {
    /// Water per point, quanta (0 on padding lanes).
    pub water: Vec<[u32; W]>,
    /// Capacity per point, quanta (0 on padding lanes).
    capacity: Vec<[u32; W]>,
    /// Dry mass per point, kg (0 on padding lanes).
    dry_mass: Vec<Lane>,
    /// The layout's row parameters with each free point's inverse mass from its dry mass plus
    /// its water (what the kernel reads instead of the layout's while water is held).
    pub params: Vec<ParamRow>,
    /// Added and evaporated since the last reset.
    added: u64,
    evaporated: u64,
    cfg: HeldWater,
}

impl Held {
    /// Every point dry, with capacities from the groom's masses.
    pub fn new(lay: &Layout, cfg: HeldWater) -> Held {
        let n_rows = lay.blocks * lay.rows;
        let mut dry_mass = vec![[0.0f32; W]; n_rows];
        let mut capacity = vec![[0u32; W]; n_rows];
        for s in 0..lay.strands {
            let (b, l) = lay.lane_of(s);
            let first = lay.strand_first[s] as usize;
            for i in 0..lay.strand_points(s) {
                let m = lay.mass[first + i];
                dry_mass[b * lay.rows + i][l] = m;
                capacity[b * lay.rows + i][l] = wet::capacity(m, cfg.capacity_ratio);
            }
        }
        Held {
            water: vec![[0; W]; n_rows],
            capacity,
            dry_mass,
            params: lay.params.clone(),
            added: 0,
            evaporated: 0,
            cfg,
        }
    }

    /// Sets each free point's inverse mass to `1 / (dry + water)`: soaked hair is heavier.
    /// A dry point keeps the layout's value bit for bit.
    pub fn refresh_masses(&mut self, lay: &Layout) {
        for (r, row) in self.params.iter_mut().enumerate() {
            for l in 0..W {
                let dry_inv = lay.params[r].inv_mass[l];
                let q = self.water[r][l];
                row.inv_mass[l] = if dry_inv == 0.0 || q == 0 {
                    dry_inv
                } else {
                    (1.0 / (self.dry_mass[r][l] as f64 + wet::to_kg(q))) as f32
                };
            }
        }
    }

    /// Wets every point up to saturation `s` (in [0, 1]) of its capacity; never removes
    /// water. What it adds is booked as added.
    pub fn soak(&mut self, s: f32) {
        for (w, c) in self.water.iter_mut().zip(&self.capacity) {
            for l in 0..W {
                let target = (c[l] as f64 * s as f64).floor() as u32;
                if w[l] < target {
                    self.added += (target - w[l]) as u64;
                    w[l] = target;
                }
            }
        }
    }

    /// Pass `dry`: each point loses `held (1 - e^(-k dt))` to the nearest quantum, with
    /// `k = (1 / dry_time) (1 + sqrt(|v| / dry_air_speed))` (the air is still, so the air
    /// speed past a point is its own speed). Order-free: integers per point.
    pub fn dry(&mut self, state: &[StateRow], dt: f32) {
        if self.cfg.dry_time <= 0.0 {
            return;
        }
        for (w, r) in self.water.iter_mut().zip(state) {
            for l in 0..W {
                if w[l] == 0 {
                    continue;
                }
                let u = r.v.get(l).length();
                let k = wet::evaporation_rate(u, self.cfg.dry_time, self.cfg.dry_air_speed);
                let e = wet::evaporate(w[l], k, dt);
                w[l] -= e;
                self.evaporated += e as u64;
            }
        }
    }

    /// Writes each point's saturation, at most 1, as its wetness.
    pub fn saturation_into(&self, wetness: &mut [Lane]) {
        for ((out, w), c) in wetness.iter_mut().zip(&self.water).zip(&self.capacity) {
            for l in 0..W {
                out[l] = wet::saturation(w[l], c[l]).min(1.0);
            }
        }
    }

    /// Dry again, with an empty ledger.
    pub fn reset(&mut self, lay: &Layout) {
        self.water.iter_mut().for_each(|w| *w = [0; W]);
        self.added = 0;
        self.evaporated = 0;
        self.refresh_masses(lay);
    }

    /// Added, held and evaporated, in quanta.
    pub fn ledger(&self) -> WaterLedger {
        WaterLedger {
            added: self.added,
            held: self.water.iter().flatten().map(|&q| q as u64).sum(),
            evaporated: self.evaporated,
        }
    }

    /// Bytes held (what a scene with held water costs).
    pub fn bytes(&self) -> usize {
        self.water.capacity() * 4 * W
            + self.capacity.capacity() * 4 * W
            + self.dry_mass.capacity() * 4 * W
            + self.params.capacity() * std::mem::size_of::<ParamRow>()
    }
}
