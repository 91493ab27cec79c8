//! The wet model's parameters (docs/WET_MODEL.md): what held water does, and the wind. Each
//! part is off unless asked for, and a part that is off costs no pass and no buffer.

use super::WaterParams;
use crate::error::{check_finite3, check_non_negative, invalid, Result};
use crate::physics::wet;
use glam::Vec3;

/// The full wet model (docs/WET_MODEL.md §1-§7): every free hair point takes water into its
/// fibres up to `capacity_ratio` times its dry mass (its capacity: what makes it limp and
/// binds it to its neighbours), holds `free_ratio` times its dry mass more between them
/// against gravity (its hold limit is the sum), and weighs its dry mass plus its water; it
/// draws in the particles that touch it up to its hold limit, bends more easily when wet,
/// holds its neighbours by liquid bridges, lets the water above its hold limit run down the
/// strand and drip from where it can run no further, and dries
/// at a first-order rate that grows with the air speed past it. Water is counted in whole
/// quanta ([`wet::WATER_QUANTUM`]) so the ledger balances exactly. Off (`enabled: false`), a
/// simulation runs the paper's model: particles only pull (eq. 2). Both backends run all of
/// it (the GPU's liquid bridges take grooms of up to a device-dependent number of points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeldWater {
    /// Whether points hold water (off: no buffer, no pass).
    pub enabled: bool,
    /// Water a kilogram of dry hair holds when saturated, kg/kg (0.3: Robbins 2012).
    pub capacity_ratio: f32,
    /// Water a kilogram of dry hair holds between its fibres against gravity, above
    /// `capacity_ratio`, kg/kg (§1; 1.0); only water above both runs along the strand and
    /// drips. 0: whatever exceeds capacity runs.
    pub free_ratio: f32,
    /// Drying time constant in still air, s; 0 never dries.
    pub dry_time: f32,
    /// Air speed at which drying runs twice as fast as in still air, m/s.
    pub dry_air_speed: f32,
    /// Rate at which `wet::ABSORB_LENGTH` (2 cm) of hair draws in a particle within `r_max`,
    /// 1/s (§2: a point asks in proportion to the hair it stands for, so a drop soaks in alike
    /// at any sampling); 0: particles are never absorbed and only pull.
    pub absorb_rate: f32,
    /// Bending stiffness of saturated hair over dry, in [0, 1] (§4); 1: no limpness.
    pub wet_bend_ratio: f32,
    /// Pull of a liquid bridge per metre of bridged hair, N/m (§5; `2 γ`); 0: no bridges.
    pub bridge_tension: f32,
    /// Distance at which a liquid bridge lets go, m (§5); 0 takes `1.5 r_min`.
    pub bridge_length: f32,
    /// Mobility of held water along a strand, 1/s (§6), over `flow_length` of hair; 0: water
    /// stays where it landed.
    pub flow_mobility: f32,
    /// Length of hair `flow_mobility` is quoted over, m (§6; 0.02): a segment `l` long passes
    /// on `flow_mobility · flow_length / l` of its running water a second, so the water runs
    /// down a strand at [`HeldWater::flow_speed`] however finely the strand is sampled.
    pub flow_length: f32,
    /// Smallest drop that leaves a point above its hold limit, kg (§6).
    pub drip_mass: f32,
}

impl HeldWater {
    /// Off, with the documented defaults for when it is switched on.
    pub const OFF: HeldWater = HeldWater {
        enabled: false,
        capacity_ratio: wet::CAPACITY_RATIO,
        free_ratio: wet::FREE_RATIO,
        dry_time: wet::DRY_TIME,
        dry_air_speed: wet::DRY_AIR_SPEED,
        absorb_rate: wet::ABSORB_RATE,
        wet_bend_ratio: wet::WET_BEND_RATIO,
        bridge_tension: 2.0 * wet::SURFACE_TENSION,
        bridge_length: 0.0,
        flow_mobility: wet::FLOW_MOBILITY,
        flow_length: wet::FLOW_LENGTH,
        drip_mass: wet::MIN_DROP_MASS,
    };
    /// On, with the documented defaults.
    pub const ON: HeldWater = HeldWater {
        enabled: true,
        ..HeldWater::OFF
    };
    /// The largest `capacity_ratio` and `free_ratio` accepted, kg/kg.
    pub const MAX_CAPACITY_RATIO: f32 = 100.0;
    /// The largest `bridge_tension` accepted, N/m (ten times water's `2 γ`).
    pub const MAX_BRIDGE_TENSION: f32 = 1.44;
    /// The largest rate (`absorb_rate`, `flow_mobility`) accepted, 1/s.
    pub const MAX_RATE: f32 = 1.0e4;
    /// The largest `flow_length` accepted, m.
    pub const MAX_FLOW_LENGTH: f32 = 1.0;

    /// Whether soaked points bend more easily (a saturation-dependent bend stiffness).
    pub fn limp(&self) -> bool {
        self.enabled && self.wet_bend_ratio < 1.0
    }

    /// Whether particles give their water to the hair.
    pub fn absorbs(&self) -> bool {
        self.enabled && self.absorb_rate > 0.0
    }

    /// Whether wet points of different strands attract.
    pub fn bridges(&self) -> bool {
        self.enabled && self.bridge_tension > 0.0
    }

    /// Whether held water runs along the strands.
    pub fn flows(&self) -> bool {
        self.enabled && self.flow_speed() > 0.0
    }

    /// How fast the water above the hold limit runs down a vertical strand, m/s:
    /// `flow_mobility · flow_length` (0.1 by default), whatever the strand's sampling.
    pub fn flow_speed(&self) -> f32 {
        self.flow_mobility * self.flow_length
    }

    /// Whether a point can come to hold more than its hold limit, and so drip: water only
    /// arrives above it by flow, absorption or a soaking past it.
    pub fn drips(&self) -> bool {
        self.flows() || self.absorbs()
    }

    /// Whether held water evaporates.
    pub fn dries(&self) -> bool {
        self.enabled && self.dry_time > 0.0
    }

    /// The bridge length in use, m: `bridge_length`, or `1.5 r_min` when it is 0.
    pub fn bridge_length_for(&self, water: &WaterParams) -> f32 {
        if self.bridge_length > 0.0 {
            self.bridge_length
        } else {
            1.5 * water.r_min
        }
    }

    /// When on, checks that the heaviest of the points `masses` (kg) holds at its hold limit
    /// no more than one water count ([`wet::MAX_WATER_MASS`]); both backends ask at creation.
    pub fn check_masses(&self, masses: &[f32]) -> Result<()> {
        if !self.enabled {
            return Ok(());
        }
        let heaviest = masses.iter().fold(0.0f32, |a, &m| a.max(m));
        let most = heaviest as f64 * (self.capacity_ratio as f64 + self.free_ratio as f64);
        if most > wet::MAX_WATER_MASS {
            return Err(invalid!(
                "held water: a point of {heaviest} kg would hold {most:e} kg, more than one water count ({:e} kg); lower held_water.capacity_ratio or free_ratio",
                wet::MAX_WATER_MASS
            ));
        }
        Ok(())
    }

    /// Checks every field (and, when on, that particles and drops fit a water count).
    pub fn validate(&self, water: &WaterParams) -> Result<()> {
        for (name, v) in [
            ("held_water.capacity_ratio", self.capacity_ratio),
            ("held_water.free_ratio", self.free_ratio),
        ] {
            if !(v.is_finite() && (0.0..=Self::MAX_CAPACITY_RATIO).contains(&v)) {
                return Err(invalid!(
                    "{name} must be in [0, {}] kg/kg, got {v}",
                    Self::MAX_CAPACITY_RATIO
                ));
            }
        }
        check_non_negative("held_water.dry_time", self.dry_time)?;
        if !(self.dry_air_speed.is_finite() && self.dry_air_speed > 0.0) {
            return Err(invalid!(
                "held_water.dry_air_speed must be finite and > 0 m/s, got {}",
                self.dry_air_speed
            ));
        }
        for (name, v) in [
            ("held_water.absorb_rate", self.absorb_rate),
            ("held_water.flow_mobility", self.flow_mobility),
        ] {
            if !(v.is_finite() && (0.0..=Self::MAX_RATE).contains(&v)) {
                return Err(invalid!("{name} must be in [0, {}] 1/s, got {v}", Self::MAX_RATE));
            }
        }
        if !(self.flow_length.is_finite() && self.flow_length > 0.0 && self.flow_length <= Self::MAX_FLOW_LENGTH) {
            return Err(invalid!(
                "held_water.flow_length must be in (0, {}] m, got {}",
                Self::MAX_FLOW_LENGTH,
                self.flow_length
            ));
        }
        if !(self.wet_bend_ratio.is_finite() && (0.0..=1.0).contains(&self.wet_bend_ratio)) {
            return Err(invalid!(
                "held_water.wet_bend_ratio must be in [0, 1], got {}",
                self.wet_bend_ratio
            ));
        }
        if !(self.bridge_tension.is_finite() && (0.0..=Self::MAX_BRIDGE_TENSION).contains(&self.bridge_tension)) {
            return Err(invalid!(
                "held_water.bridge_tension must be in [0, {}] N/m, got {}",
                Self::MAX_BRIDGE_TENSION,
                self.bridge_tension
            ));
        }
        if !(self.bridge_length.is_finite() && (0.0..=super::MAX_R_MAX).contains(&self.bridge_length)) {
            return Err(invalid!(
                "held_water.bridge_length must be in [0, {}] m, got {}",
                super::MAX_R_MAX,
                self.bridge_length
            ));
        }
        let max = wet::MAX_WATER_MASS as f32;
        if !(self.drip_mass.is_finite() && self.drip_mass > 0.0 && self.drip_mass <= max) {
            return Err(invalid!(
                "held_water.drip_mass must be in (0, {max:e}] kg, got {}",
                self.drip_mass
            ));
        }
        if self.enabled && water.particle_mass > max {
            return Err(invalid!(
                "with held water, water particle mass must be at most {max:e} kg (one water count), got {}",
                water.particle_mass
            ));
        }
        if self.bridges() && self.bridge_length_for(water) <= 0.0 {
            return Err(invalid!(
                "liquid bridges need a bridge length: set held_water.bridge_length or water r_min above 0"
            ));
        }
        Ok(())
    }
}

/// A uniform wind with gusts (docs/WET_MODEL.md §8): `velocity` times `1 + gust` times the
/// mean of three sines whose frequencies and phases come from `seed`. It acts by linear drag
/// on hair points (`c_i (W - v)`, [`crate::SimParams::hair_drag`]) and particles
/// (`water.drag (W - v)`), and dries hair faster. Calm (zero velocity) adds nothing to any pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// Mean wind velocity, m/s.
    pub velocity: Vec3,
    /// Gust amplitude, a fraction of the mean in [0, 1].
    pub gust: f32,
    /// Seed of the gusts' frequencies and phases.
    pub seed: u32,
}

impl Wind {
    /// No wind.
    pub const CALM: Wind = Wind {
        velocity: Vec3::ZERO,
        gust: 0.0,
        seed: 0,
    };
    /// The fastest mean wind accepted, m/s (a hurricane).
    pub const MAX_SPEED: f32 = 100.0;

    /// Whether any wind blows.
    pub fn blows(&self) -> bool {
        self.velocity != Vec3::ZERO
    }

    /// The wind at simulation time `t`, s.
    pub fn at(&self, t: f64) -> Vec3 {
        if self.gust > 0.0 {
            wet::gust(self.velocity, self.gust, self.seed, t)
        } else {
            self.velocity
        }
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<()> {
        check_finite3("wind velocity", self.velocity.to_array())?;
        if self.velocity.length() > Self::MAX_SPEED {
            return Err(invalid!(
                "wind speed must be at most {} m/s, got {}",
                Self::MAX_SPEED,
                self.velocity.length()
            ));
        }
        if !(self.gust.is_finite() && (0.0..=1.0).contains(&self.gust)) {
            return Err(invalid!("wind gust must be in [0, 1], got {}", self.gust));
        }
        Ok(())
    }
}

impl Default for Wind {
    fn default() -> Self {
        Wind::CALM
    }
}
