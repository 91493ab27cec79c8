//! The wet model through the C ABI (since 0.2.0; docs/WET_MODEL.md): its parameters and the
//! wind as parts of `WetHairSimDesc`, soaking, the wind each frame, and the water ledger in
//! `WetHairStats`.

use super::boundary::{Fail, WetHairResult};
use super::sim::WetHairSim;
use crate::params::{HeldWater, Wind};
use glam::Vec3;

/// Kilograms of water in one unit of the ledger's counts (`WetHairStats::water_*`): water is
/// counted in whole nanograms so that the ledger balances exactly.
pub const WETHAIR_WATER_QUANTUM_KG: f64 = crate::physics::wet::WATER_QUANTUM;

/// The full wet model (docs/WET_MODEL.md), on both backends. Off (`enabled` 0, the default)
/// a simulation runs the paper's model. Rates of 0 switch their part off; no part costs
/// anything while off. The water held between the fibres is
/// `WetHairSimDesc::held_water_free_ratio` (since 0.6.0: this struct cannot grow), and the
/// length flow's mobility is quoted over `WetHairSimDesc::held_water_flow_length` (0.7.0).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WetHairHeldWater {
    /// 1: hair points hold water (weight, limpness, absorption, bridges, flow, drip, drying);
    /// 0: off. Other values are refused.
    pub enabled: u32,
    /// Water a kilogram of dry hair takes into its fibres when saturated, kg/kg, 0..=100.
    /// Default 0.3.
    pub capacity_ratio: f32,
    /// Drying time constant in still air, s; 0 never dries. Default 1200.
    pub dry_time: f32,
    /// Air speed at which drying runs twice as fast, m/s, > 0. Default 1.
    pub dry_air_speed: f32,
    /// Rate at which 2 cm of hair draws in a particle within r_max, 1/s (a point asks in
    /// proportion to the hair it stands for); 0: never. Default 20.
    pub absorb_rate: f32,
    /// Bending stiffness of saturated hair over dry, 0..=1 (1: not limp). Default 0.5.
    pub wet_bend_ratio: f32,
    /// Pull of a liquid bridge per metre of bridged hair, N/m, 0..=1.44; 0: no bridges.
    /// Default 0.144 (twice water's surface tension).
    pub bridge_tension: f32,
    /// Distance at which a bridge lets go, m; 0: 1.5 r_min (the default).
    pub bridge_length: f32,
    /// Mobility of held water along a strand, 1/s, over `WetHairSimDesc::held_water_flow_length`
    /// of hair (0.02 m; since 0.7.0: before, over each segment, so finer grooms drained
    /// slower); 0: it stays put. Default 5: the water runs down a strand at 0.1 m/s.
    pub flow_mobility: f32,
    /// Smallest drop that leaves a point above its hold limit, kg, > 0. Default 4.2e-6.
    pub drip_mass: f32,
}

impl From<HeldWater> for WetHairHeldWater {
    fn from(h: HeldWater) -> Self {
        WetHairHeldWater {
            enabled: h.enabled as u32,
            capacity_ratio: h.capacity_ratio,
            dry_time: h.dry_time,
            dry_air_speed: h.dry_air_speed,
            absorb_rate: h.absorb_rate,
            wet_bend_ratio: h.wet_bend_ratio,
            bridge_tension: h.bridge_tension,
            bridge_length: h.bridge_length,
            flow_mobility: h.flow_mobility,
            drip_mass: h.drip_mass,
        }
    }
}

impl WetHairHeldWater {
    /// As [`HeldWater`] (its floats are checked by `SimParams::validate`).
    pub(crate) fn params(&self) -> Result<HeldWater, Fail> {
        let enabled = match self.enabled {
            0 => false,
            1 => true,
            v => {
                return Err(Fail(
                    WetHairResult::WETHAIR_ERROR_INVALID_ARGUMENT,
                    format!("held_water.enabled must be 0 or 1, got {v}"),
                ))
            }
        };
        Ok(HeldWater {
            enabled,
            capacity_ratio: self.capacity_ratio,
            free_ratio: crate::physics::wet::FREE_RATIO,
            dry_time: self.dry_time,
            dry_air_speed: self.dry_air_speed,
            absorb_rate: self.absorb_rate,
            wet_bend_ratio: self.wet_bend_ratio,
            bridge_tension: self.bridge_tension,
            bridge_length: self.bridge_length,
            flow_mobility: self.flow_mobility,
            flow_length: crate::physics::wet::FLOW_LENGTH,
            drip_mass: self.drip_mass,
        })
    }
}

/// A uniform wind with gusts: `velocity` times `1 + gust` times the mean of three sines whose
/// frequencies and phases come from `seed`. Drags hair (with `air_drag` > 0) and particles,
/// and dries held water faster. Both backends.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WetHairWind {
    /// Mean velocity, m/s, at most 100 m/s. Default (0, 0, 0): calm.
    pub velocity: [f32; 3],
    /// Gust amplitude as a fraction of the mean, 0..=1. Default 0.
    pub gust: f32,
    /// Seed of the gusts. Default 0.
    pub seed: u32,
}

impl From<Wind> for WetHairWind {
    fn from(w: Wind) -> Self {
        WetHairWind {
            velocity: w.velocity.to_array(),
            gust: w.gust,
            seed: w.seed,
        }
    }
}

impl From<WetHairWind> for Wind {
    fn from(w: WetHairWind) -> Self {
        Wind {
            velocity: Vec3::from(w.velocity),
            gust: w.gust,
            seed: w.seed,
        }
    }
}

/// Wets every hair point up to `s` times its hold limit (its capacity and the water between
/// its fibres), as when a character steps out of water; never removes water. 1 is as wet as
/// hair stays; above 1 (up to 10, since 0.6.0) the excess runs down the strands and drips,
/// as from hair just out of a bath, and is refused when nothing drips (`flow_mobility` and
/// `absorb_rate` both 0). Needs `held_water.enabled` (else `WETHAIR_ERROR_UNSUPPORTED`).
///
/// # Safety
/// `sim` is valid.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_soak(sim: *mut WetHairSim, s: f32) -> WetHairResult {
    boundary!({
        nonnull_mut!(sim, "sim").0.soak(s)?;
        Ok(())
    })
}

/// Sets the wind from the next step on (checked: finite, at most 100 m/s, gust in [0, 1]);
/// a bad wind changes nothing. The gusts follow the simulation's own clock.
///
/// # Safety
/// `sim` is valid; `wind` points to a `WetHairWind`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_wind(sim: *mut WetHairSim, wind: *const WetHairWind) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let w = *nonnull!(wind, "wind");
        s.0.set_wind(w.into())?;
        Ok(())
    })
}

/// Rain: drops appear uniformly over a horizontal rectangle and fall straight down (-z).
/// Each drop weighs `water.particle_mass`; drop `k` comes from `(seed, k)` alone, so runs
/// and backends rain alike.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WetHairRain {
    /// Centre of the rectangle drops start from, world space, m.
    pub center: [f32; 3],
    /// The rectangle's extent along x and y, m (each >= 0).
    pub size: [f32; 2],
    /// Drops per second, 0..=1e6.
    pub rate: f32,
    /// Fall speed, m/s, 0..=100.
    pub speed: f32,
    /// Seed of the drops' places.
    pub seed: u32,
}

/// A spray: drops leave `origin` within `half_angle` of `direction` at `speed`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WetHairSpray {
    /// Nozzle position, world space, m.
    pub origin: [f32; 3],
    /// The cone's axis (non-zero).
    pub direction: [f32; 3],
    /// The cone's half-angle, radians, 0..=pi.
    pub half_angle: f32,
    /// Drops per second, 0..=1e6.
    pub rate: f32,
    /// Drop speed, m/s, 0..=100.
    pub speed: f32,
    /// Seed of the drops' directions.
    pub seed: u32,
}

/// Starts, changes (`rain` non-NULL) or stops (NULL) the rain from the next step on. Drops
/// that do not fit `water.capacity` are left out. A bad rain (NaN, negative size, rate or
/// speed out of range) is refused by name and changes nothing.
///
/// # Safety
/// `sim` is valid; `rain` is NULL or points to a `WetHairRain`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_rain(sim: *mut WetHairSim, rain: *const WetHairRain) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let r = rain.as_ref().map(|r| crate::emit::Rain {
            center: Vec3::from(r.center),
            size: r.size,
            rate: r.rate,
            speed: r.speed,
            seed: r.seed,
        });
        s.0.set_rain(r)?;
        Ok(())
    })
}

/// Starts, changes (`spray` non-NULL) or stops (NULL) the spray from the next step on, as
/// `wethair_sim_set_rain` does the rain.
///
/// # Safety
/// `sim` is valid; `spray` is NULL or points to a `WetHairSpray`.
#[no_mangle]
pub unsafe extern "C" fn wethair_sim_set_spray(sim: *mut WetHairSim, spray: *const WetHairSpray) -> WetHairResult {
    boundary!({
        let s = nonnull_mut!(sim, "sim");
        let sp = spray.as_ref().map(|p| crate::emit::Spray {
            origin: Vec3::from(p.origin),
            direction: Vec3::from(p.direction),
            half_angle: p.half_angle,
            rate: p.rate,
            speed: p.speed,
            seed: p.seed,
        });
        s.0.set_spray(sp)?;
        Ok(())
    })
}
