//! The wet model's laws (docs/WET_MODEL.md), each written once: capacity, saturation,
//! absorption with the particle's grant, limpness, liquid-bridge cohesion, flow along a strand,
//! drip, drying and gusts. Pure functions of their inputs, so both backends and the tests read
//! the same definition; the CPU backend's passes call them (the GPU's are to come).
//!
//! Water is counted in whole [`WATER_QUANTUM`]s (`u32`): every transfer (absorb, flow, drip,
//! dry) moves an integer from one count to another, so the ledger balances exactly, in any
//! order, on any thread count, and with integer atomics on the GPU. Rates are floats; only the
//! amounts they move are rounded, once, to whole quanta.

use super::lanes::{u32_as_f32, u32_as_f64, Lane, L3, W};
use super::per_length::PerLength;
use super::rounding::{floor_nonneg_lanes, round_nonneg};
use glam::Vec3;

/// The unit water is counted in, kg (a nanogram): a `u32` count holds up to 4.29 g, far above
/// what one hair point or one drop holds, and resolves a point's capacity to parts per million.
pub const WATER_QUANTUM: f64 = 1.0e-12;
/// The most water one count may describe, kg (`u32::MAX` quanta, less headroom for a step's
/// inflow): capacities and particle masses above it are refused.
pub const MAX_WATER_MASS: f64 = (1u64 << 31) as f64 * WATER_QUANTUM;
/// The most a point takes by absorption, quanta (the largest capacity allowed): however many
/// drops reach it in one substep, it stops here, and the drops keep the rest. With the flow's
/// bound ([`flow_inflow_bound`]) no point's count can wrap.
pub const HELD_LIMIT: u32 = 1 << 31;

/// The most a point holding `start` quanta at the flow pass's start may receive from each of
/// its two neighbours: half its room below `u32::MAX`, so that both together cannot wrap its
/// count (a transfer is cut to it, never raised; the sender keeps the rest).
#[inline]
pub fn flow_inflow_bound(start: u32) -> u32 {
    (u32::MAX - start) / 2
}

/// `kg` as whole quanta, to nearest (negative and NaN give 0; above `u32::MAX` saturates).
#[inline]
pub fn to_quanta(kg: f64) -> u32 {
    (kg / WATER_QUANTUM).round().clamp(0.0, u32::MAX as f64) as u32
}

/// Quanta as kg.
#[inline]
pub fn to_kg(q: u32) -> f64 {
    q as f64 * WATER_QUANTUM
}

/// Water a kilogram of dry hair holds when saturated, kg/kg (Robbins 2012, ch. 9: ~30 %).
pub const CAPACITY_RATIO: f32 = 0.3;
/// Water a kilogram of dry hair holds between its fibres against gravity, above what the
/// fibres take in, kg/kg (docs/WET_MODEL.md §1: the pores of a wet bundle, about 60 % of its
/// volume, full of water, `0.6 / 0.4 × 1.0 / 1.32`, to one figure).
pub const FREE_RATIO: f32 = 1.0;
/// Rate at which hair draws in a droplet it touches, 1/s, over [`ABSORB_LENGTH`] of hair.
pub const ABSORB_RATE: f32 = 20.0;
/// Length of hair [`ABSORB_RATE`] is quoted over, m: the paper scene's segment, on which the
/// rate was first given per point. A point asks in proportion to the hair it stands for
/// ([`absorb_share`]), so a drop soaks into a centimetre of hair at the same rate however
/// many points sample it.
pub const ABSORB_LENGTH: f32 = 0.02;
/// `1 / (2 ABSORB_LENGTH)`, exact in f32: [`absorb_share`]'s factor, on both backends.
pub const ABSORB_SHARE_SCALE: f32 = 0.5 / ABSORB_LENGTH;
/// A particle left holding less than this fraction of a full particle (`particle_mass`) is
/// taken whole by the point that asked it for most: absorption is exponential and would
/// otherwise never finish.
pub const ABSORB_LAST_FRACTION: f64 = 1.0e-3;
/// Bending stiffness of saturated hair over dry (Robbins 2012, ch. 9: the modulus in water is
/// about half of its value at ambient humidity).
pub const WET_BEND_RATIO: f32 = 0.5;
/// Surface tension of water at 20 °C, N/m.
pub const SURFACE_TENSION: f32 = 0.072;
/// Mobility of held water along a strand, 1/s, over [`FLOW_LENGTH`] of hair.
pub const FLOW_MOBILITY: f32 = 5.0;
/// Length of hair [`FLOW_MOBILITY`] is quoted over, m: the paper scene's segment, on which the
/// law was first written per segment. Running water moves at `FLOW_MOBILITY · FLOW_LENGTH`
/// (0.1 m/s) down a vertical strand.
pub const FLOW_LENGTH: f32 = 0.02;
/// The smallest drop that leaves a point: the mass of a 2 mm water drop, kg.
pub const MIN_DROP_MASS: f32 = 4.2e-6;
/// Drying time constant in still air, s.
pub const DRY_TIME: f32 = 1200.0;
/// Air speed at which drying runs twice as fast as in still air, m/s.
pub const DRY_AIR_SPEED: f32 = 1.0;

/// Most water a point of dry mass `dry_mass` (kg) holds, in quanta: capacity follows the
/// hair's mass, so it is per metre of hair whatever the sampling.
#[inline]
pub fn capacity(dry_mass: f32, ratio: f32) -> u32 {
    to_quanta(dry_mass as f64 * ratio as f64)
}

/// The most water a point of dry mass `dry_mass` holds against gravity (its hold limit), in
/// quanta: its capacity and the water between its fibres, `(capacity_ratio + free_ratio)`
/// times its dry mass. Absorption fills a point to it; only water above it runs along the
/// strand, and a point drips what exceeds it where the water cannot run on.
#[inline]
pub fn hold_limit(dry_mass: f32, capacity_ratio: f32, free_ratio: f32) -> u32 {
    to_quanta(dry_mass as f64 * (capacity_ratio as f64 + free_ratio as f64))
}

/// The capacity and hold limit (quanta) of a point of dry mass `dry_mass` (kg) standing for
/// `bundle` strands' hair (`physics/bundles.rs`; 1 without guides): those of `bundle` times the
/// mass, each at most [`HELD_LIMIT`], what one count holds. A groom's own points are checked
/// to fit at create (`HeldWater::check_masses`); a bundle may not, and then its guide holds no
/// more than the count (docs/GUIDES.md "Water").
#[inline]
pub fn bundle_limits(dry_mass: f32, bundle: f32, capacity_ratio: f32, free_ratio: f32) -> (u32, u32) {
    let m = dry_mass * bundle;
    (
        capacity(m, capacity_ratio).min(HELD_LIMIT),
        hold_limit(m, capacity_ratio, free_ratio).min(HELD_LIMIT),
    )
}

/// The most a soaking may fill a point to, as a multiple of its hold limit: ten times what the
/// hair holds against gravity is hair fresh out of a bath.
pub const MAX_SOAK: f32 = 10.0;

/// What a soaking to `s` (in `0..=MAX_SOAK`) fills a point of hold limit `hold` to, quanta:
/// `floor(hold s)`, at most [`HELD_LIMIT`]. Above 1 the water past the hold limit runs down
/// the strand and drips (a dunk).
#[inline]
pub fn soak_target(hold: u32, s: f32) -> u32 {
    ((hold as f64 * s as f64).floor() as u32).min(HELD_LIMIT)
}

/// Saturation `held / capacity` (0 where a point can hold nothing); may exceed 1 before a drip.
/// With a point's hold limit for `capacity`, how full it is: what absorption asks by and the
/// vertices show.
#[inline]
pub fn saturation(held: u32, capacity: u32) -> f32 {
    if capacity > 0 {
        held as f32 / capacity as f32
    } else {
        0.0
    }
}

/// [`saturation`] of a row of eight points, the same bits lane by lane, as vectors (each
/// lane's divide computed, then chosen).
#[inline(always)]
pub fn saturation_lanes(held: &[u32; W], capacity: &[u32; W]) -> Lane {
    let (h, c) = (u32_as_f32(held), u32_as_f32(capacity));
    let mut s = [0.0f32; W];
    for l in 0..W {
        let d = h[l] / c[l];
        s[l] = if capacity[l] > 0 { d } else { 0.0 };
    }
    s
}

/// The water one quantum adds to each strand of a point that stands for `bundle` strands'
/// hair (a guide and its followers, docs/GUIDES.md "Water"; 1 without guides), kg:
/// `WATER_QUANTUM / bundle` in single precision. With `bundle` 1 it is `WATER_QUANTUM` as `f32`
/// exactly, so a groom without guides keeps its bits.
#[inline]
pub fn quantum_per_strand(bundle: f32) -> f32 {
    WATER_QUANTUM as f32 / bundle
}

/// The inverse mass of a free point of dry mass `dry_mass` (kg) holding `held` quanta, one
/// quantum adding `quantum` kg to it ([`quantum_per_strand`]): `1 / (m_dry + m_w)`, in single
/// precision as the GPU computes it (a relative error of a few parts in 10^7, far below any
/// mass the groom is given to).
#[inline(always)]
pub fn wet_inv_mass(dry_mass: f32, held: u32, quantum: f32) -> f32 {
    inv_mass_of(dry_mass, held as f32, quantum)
}

/// [`wet_inv_mass`] with the water already as `f32` (its conversion vectorised apart).
#[inline(always)]
fn inv_mass_of(dry_mass: f32, held_f: f32, quantum: f32) -> f32 {
    1.0 / (dry_mass + held_f * quantum)
}

/// [`wet_inv_mass`] of a row of eight points, the same bits, as vectors: one divide for the
/// row, where the double-precision form it replaces was eight scalar ones.
#[inline(always)]
pub fn wet_inv_mass_lanes(dry_mass: &Lane, held: &[u32; W], quantum: &Lane) -> Lane {
    let q = u32_as_f32(held);
    let mut inv = [0.0f32; W];
    for l in 0..W {
        inv[l] = inv_mass_of(dry_mass[l], q[l], quantum[l]);
    }
    inv
}

/// The factor on bending stiffness at saturation `s`: 1 dry, `wet_ratio` saturated, linear
/// between (a point over capacity is as limp as a saturated one).
#[inline]
pub fn bend_scale(s: f32, wet_ratio: f32) -> f32 {
    1.0 - (1.0 - wet_ratio) * s.clamp(0.0, 1.0)
}

/// The absorption distance weight: 1 within `r_min` of the particle, falling linearly to 0 at
/// `r_max` (where eq. 2's pull ends).
#[inline]
pub fn absorb_weight(d: f32, r_min: f32, r_max: f32) -> f32 {
    ((r_max - d) / (r_max - r_min)).clamp(0.0, 1.0)
}

/// What one hair point standing for [`ABSORB_LENGTH`] of hair asks of one particle holding
/// `particle` quanta in a substep `h`, in quanta (rounded down): the fraction `1 - e^(-rate h)`
/// of the particle's water, times the distance weight `weight` (1 at `r_min`, 0 at `r_max`)
/// and the point's room `1 - s`, `s` its water over its hold limit.
#[inline]
pub fn absorb_demand(particle: u32, weight: f32, s: f32, rate: f32, h: f32) -> u32 {
    absorb_demand_taking(particle, weight, s, absorb_take(rate, h))
}

/// The fraction of a particle's water a point within `r_min` would take in a substep `h` at
/// rate `rate`: `1 - e^(-rate h)` (one value per substep: the passes work it out once, not
/// once per pair).
#[inline]
pub fn absorb_take(rate: f32, h: f32) -> f32 {
    -(-rate * h).exp_m1()
}

/// The length of hair a point stands for over [`ABSORB_LENGTH`]: half of each rest segment it
/// ends (`before`, `after`, m; 0 where the strand has none), so a strand's shares sum to its
/// length over `ABSORB_LENGTH` however finely it is sampled (docs/WET_MODEL.md §2).
#[inline]
pub fn absorb_share(before: f32, after: f32) -> f32 {
    ABSORB_SHARE.at(before, after)
}

/// [`absorb_share`] as a per-length coefficient (1 over [`ABSORB_LENGTH`]), for a block's rows
/// at once ([`PerLength::row`]).
pub(crate) const ABSORB_SHARE: PerLength = PerLength {
    per_point: 0.0,
    scale: ABSORB_SHARE_SCALE,
};

/// The fraction a point of share `share` ([`absorb_share`]) takes of a particle within `r_min`
/// in a substep whose take over [`ABSORB_LENGTH`] is `take` ([`absorb_take`]): in proportion,
/// and never more than the whole particle.
#[inline(always)]
pub fn absorb_take_at(take: f32, share: f32) -> f32 {
    (take * share).min(1.0)
}

/// [`absorb_demand`] with the substep's fraction `take` ([`absorb_take`]) worked out.
#[inline(always)]
pub fn absorb_demand_taking(particle: u32, weight: f32, s: f32, take: f32) -> u32 {
    let d = take as f64 * particle as f64 * weight.clamp(0.0, 1.0) as f64 * (1.0 - s).max(0.0) as f64;
    d.floor() as u32
}

/// A point's room below its hold limit: what a grant to it may take at most, from its water
/// `held` at the substep's start (docs/WET_MODEL.md §2). A particle of 1 g asks for about
/// 80 mg of it in a substep, and a centimetre of a real groom holds about 13 mg.
#[inline]
pub fn hold_room(held: u32, hold: u32) -> u32 {
    hold.saturating_sub(held)
}

/// What a particle holding `particle` quanta grants one demand `demand` when all its demands
/// sum to `total`: the demand itself while the particle has enough, else its share of the
/// particle, rounded down, so the grants never sum to more than the particle holds (the
/// particle keeps what rounding leaves, and gives it in a later substep).
#[inline]
pub fn grant(particle: u32, demand: u32, total: u64) -> u32 {
    if total <= particle as u64 {
        demand
    } else {
        (demand as u64 * particle as u64 / total) as u32
    }
}

/// The stiffness of the liquid bridge between two wet points of different strands, N/m:
/// `4 kappa len min(s_i, s_j) / d_b`, with `kappa` the pull per metre of bridged hair (about
/// `2 γ`), `len` the two points' mean length of hair (m) and `d_b` the bridge length. With
/// [`bridge_scale`] the pull is `kappa len s` at its peak (`d_b / 2`) and zero at contact and
/// at `d_b`: a zero-length spring that lets go, smooth where the points meet.
#[inline]
pub fn bridge_stiffness(kappa: f32, len: f32, s_i: f32, s_j: f32, d_b: f32) -> f32 {
    if d_b <= 0.0 {
        return 0.0;
    }
    4.0 * kappa * len * s_i.min(s_j).clamp(0.0, 1.0) / d_b
}

/// A point takes part in liquid bridges only while it holds at least one part in this many of
/// its capacity (5 %): less is a film too thin to span the gap to another fibre (its pull
/// would be at most 5 % of a soaked pair's). Flow and light rain leave such films along every
/// strand the water ran down: on the paper scene 200 frames after a soaking four wet points in
/// five hold under 1 %, and on a 100,000-strand groom after 100 frames of rain seven bridging
/// points in eight held under 5 %, so leaving them out is most of what the bridges' search
/// and bookkeeping cost (docs/WET_MODEL.md §5 has the figures).
pub const BRIDGE_MIN_PARTS: u32 = 20;

/// Whether a point holding `held` of its `capacity` quanta takes part in liquid bridges:
/// any water, and at least `capacity / BRIDGE_MIN_PARTS` rounded up (integers, so both
/// backends decide alike). Written as `BRIDGE_MIN_PARTS held >= capacity` (the same test for
/// a whole `held`), which runs as vectors where the divide did not; in 32 bits, eight lanes a
/// vector: where the product would pass `u32::MAX` it passes any capacity, so such a `held`
/// bridges outright.
#[inline(always)]
pub fn can_bridge(held: u32, capacity: u32) -> bool {
    const NO_WRAP: u32 = u32::MAX / BRIDGE_MIN_PARTS;
    (held > 0) & ((held > NO_WRAP) | (held.wrapping_mul(BRIDGE_MIN_PARTS) >= capacity))
}

/// The most bridges one point holds: a fibre in a bundle of parallel fibres touches at most six
/// others (hexagonal packing), and a point keeps a pair only when each is among the other's
/// six nearest. This bounds the passes' cost by the points, not by how dense a clump gets.
pub const MAX_BRIDGES: usize = 6;

/// Each step searches the points whose host index is the step's number modulo this (and every
/// point that searched and found no neighbour, [`bridge_searches`]): a point's nearest are at most this many steps (133 ms at
/// 60 Hz) old. Bridges form and break over tenths of a second; the search is the model's
/// dearest part (8 turns cost 15 % less than 4 on the bench's paper scene). 16 would cost
/// 10 % less again, but the soaked paper scene then no longer stays clumped to 0.7 of dry
/// for a second (`tests/wet_model.rs`): bridges that wait longer hold fewer points.
pub const BRIDGE_SEARCH_TURNS: u32 = 8;

/// Whether host point `host` is searched in step `turn` (the step count modulo
/// [`BRIDGE_SEARCH_TURNS`]); both backends number points as the host does.
#[inline]
pub fn bridge_search_turn(host: u32, turn: u32) -> bool {
    host % BRIDGE_SEARCH_TURNS == turn
}

/// Whether a point that takes part in bridges searches this step: on its turn
/// ([`bridge_search_turn`]), or when it has searched since it became wet and found no
/// neighbour (what catches strands that drift within reach). A point that has just become
/// wet waits for its turn, at most `BRIDGE_SEARCH_TURNS - 1` steps: a soaking wets every
/// point at once, and each searching at once made that step's search cost eight steps'.
#[inline]
pub fn bridge_searches(host: u32, turn: u32, neighbours: u32, searched: bool) -> bool {
    bridge_search_turn(host, turn) || (neighbours == 0 && searched)
}

/// The factor `m` such that a bridge of stiffness `c` pulls point i with `m (x_j - x_i)` at
/// distance `r`: `c (1 - r / d_b)` below the bridge length, else 0. The same for both points,
/// so the pair's forces are exact negatives.
#[inline]
pub fn bridge_scale(c: f32, r: f32, d_b: f32) -> f32 {
    if r < d_b {
        c * (1.0 - r / d_b)
    } else {
        0.0
    }
}

/// The drying rate at air speed `u` past the point (m/s), 1/s: `(1 / tau) (1 + sqrt(u / u_ref))`
/// (forced convection over a cylinder: mass transfer grows as the square root of speed).
#[inline(always)]
pub fn evaporation_rate(u: f32, tau: f32, u_ref: f32) -> f32 {
    (1.0 + (u.abs() / u_ref).sqrt()) / tau
}

/// [`evaporation_rate`] of eight points at once, the same bits. Its own loop over the lanes:
/// computed inside the loop that finds the speeds, it stayed scalar (a lane at a time, through
/// the stack), and it was most of the drying pass.
#[inline(always)]
pub fn evaporation_rate_lanes(u: &Lane, tau: f32, u_ref: f32) -> Lane {
    let mut k = [0.0f32; W];
    for l in 0..W {
        k[l] = evaporation_rate(u[l], tau, u_ref);
    }
    k
}

/// The quanta that evaporate from `held` in `h` seconds at rate `k`: `held (1 - e^(-k h))`
/// to nearest (the exact decay, so the law does not depend on the step size), and at least
/// one while any water and any rate are left, so hair dries completely. A step's drying is
/// tiny (`k h` about 1e-5 at the defaults) and takes [`evaporate_small`]'s single precision;
/// larger parts take double precision.
#[inline]
pub fn evaporate(held: u32, k: f32, h: f32) -> u32 {
    let x = k * h;
    if small(x) {
        return evaporate_small(held as f32, x, held);
    }
    evaporated_part(held, one_minus_exp_neg(k as f64 * h as f64))
}

/// Below this `k h`, [`evaporate`] runs in single precision, as the GPU does.
const F32_SERIES_BELOW: f32 = 1.0 / 1024.0;

/// Whether [`evaporate`] takes `x = k h` in single precision: from 0 up to
/// [`F32_SERIES_BELOW`] (not NaN, not negative).
#[inline(always)]
fn small(x: f32) -> bool {
    (0.0..F32_SERIES_BELOW).contains(&x)
}

/// [`evaporate`] for `x = k h` below [`F32_SERIES_BELOW`], in single precision (`held_f` is
/// `held` as `f32`): `1 - e^(-x)` by its series to the cube, whose first left-out term is under
/// 4e-11 of the result (below an `f32`'s resolution), then `held` times it to nearest. The
/// product is under 2^22, so its error is a quantum or two at the most, and it converts
/// through `i32`. Eight lanes of it are one AVX2 vector each, where the double-precision form
/// was two and its rounding more; the drying was a third of the settling pass on a groom
/// under rain.
#[inline(always)]
fn evaporate_small(held_f: f32, x: f32, held: u32) -> u32 {
    let frac = x * (1.0 - x * (0.5 - x * (1.0 / 6.0)));
    let lost = held_f * frac;
    // SAFETY: `lost` is finite and within 0..=2^22 (`x` is in 0..2^-10, `held_f` at most
    // 2^32), so the truncation is exact in `i32`; unchecked, it is one vector
    // instruction for eight lanes, where `as` (which saturates) was eight scalar ones.
    let t: i32 = unsafe { lost.to_int_unchecked() };
    let r = (t + (lost - t as f32 >= 0.5) as i32) as u32;
    if r == 0 && held > 0 && frac > 0.0 {
        1
    } else {
        r.min(held)
    }
}

/// [`evaporate`] on a row of eight points at rates `k`: the same bits lane by lane, as
/// vectors when every lane's `k h` is small (as a step's drying is), else lane by lane.
/// Always inlined, so the CPU's pass compiles it for AVX2 where it runs there (left to the
/// inliner, it was sometimes called out of line).
#[inline(always)]
pub fn evaporate_lanes(held: &[u32; W], k: &Lane, h: f32) -> [u32; W] {
    let mut x = [0.0f32; W];
    for l in 0..W {
        x[l] = k[l] * h;
    }
    // A fold, not `all`: no branch a lane.
    if !x.iter().fold(true, |all, &x| all & small(x)) {
        return std::array::from_fn(|l| evaporate(held[l], k[l], h));
    }
    let held_f = u32_as_f32(held);
    let mut e = [0u32; W];
    for l in 0..W {
        e[l] = evaporate_small(held_f[l], x[l], held[l]);
    }
    e
}

/// The quanta `held` loses when a part `frac` of it evaporates: to nearest, and at least one
/// while any water and any part are left.
#[inline]
fn evaporated_part(held: u32, frac: f64) -> u32 {
    let e = round_nonneg(held as f64 * frac) as u32;
    if e == 0 && held > 0 && frac > 0.0 {
        1
    } else {
        e.min(held)
    }
}

/// Below this, [`one_minus_exp_neg`] takes its series.
const SERIES_BELOW: f64 = 1.0 / 64.0;

/// `1 - e^(-x)` for `x >= 0`. Below 1/64 (a frame's drying is about 1e-4) by its series to
/// the seventh power, whose first left-out term is under 1e-17 of the result (so it agrees
/// with `-(-x).exp_m1()` to the last bit or two: the quanta it rounds to differ at most by one,
/// where a product falls on a half);
/// above, by `exp_m1`. The series is a few multiplies where `exp_m1` is a libm call per point.
#[inline]
pub fn one_minus_exp_neg(x: f64) -> f64 {
    if x < SERIES_BELOW {
        one_minus_exp_neg_series(x)
    } else {
        -(-x).exp_m1()
    }
}

/// The series of [`one_minus_exp_neg`]: `x - x^2/2 + x^3/6 - ...`, Horner, by multiplies (a
/// divide in the chain costs more than the libm call saves).
#[inline(always)]
fn one_minus_exp_neg_series(x: f64) -> f64 {
    const C: [f64; 7] = [
        1.0,
        -0.5,
        1.0 / 6.0,
        -1.0 / 24.0,
        1.0 / 120.0,
        -1.0 / 720.0,
        1.0 / 5040.0,
    ];
    x * (C[0] + x * (C[1] + x * (C[2] + x * (C[3] + x * (C[4] + x * (C[5] + x * C[6]))))))
}

/// Whether held water at a strand point with effective gravity `g_eff` (gravity minus the
/// point's acceleration) runs toward a neighbour in unit direction `t`: the flow law's test.
#[inline]
pub fn runs_toward(g_eff: Vec3, t: Vec3) -> bool {
    g_eff.dot(t) > 0.0
}

/// The drop (quanta) that leaves a point holding `held` of its hold limit `hold`
/// ([`hold_limit`]): the excess over it once it reaches `min_drop`, else 0 (the excess waits
/// for more). Only points the water cannot run on from drip (a hanging strand's tip; see
/// [`runs_toward`]).
#[inline]
pub fn drip(held: u32, hold: u32, min_drop: u32) -> u32 {
    let excess = held.saturating_sub(hold);
    if excess >= min_drop && excess > 0 {
        excess
    } else {
        0
    }
}

/// The water a point holding `held` of its hold limit `hold` lets run along the strand: what
/// exceeds the limit (the rest is held in and between the fibres against gravity).
#[inline(always)]
pub fn running(held: u32, hold: u32) -> u32 {
    held.saturating_sub(hold)
}

/// Moves one strand's held water (quanta per point, updated in place; `hold` each point's hold
/// limit) one step `h` along its segments toward where the effective gravity `g - a` points
/// (`x` positions, `a` accelerations). Each end of a segment of length `l` sends
/// `h (speed / l) running (g - a).t / |g|` away from itself when that is positive, `running`
/// its water above its hold limit ([`running`]; `speed`: [`crate::HeldWater::flow_speed`], so
/// the water moves `speed` m/s along a vertical strand however many points sample it),
/// computed from the water at the start of the step (the order points are visited does not
/// matter), rounded down to whole quanta, and scaled so no point sends more than may run. Every transfer is one integer taken from one point
/// and given to its neighbour: the strand's total never changes. The strand runs as lane 0
/// of [`flow_lanes`], which the CPU backend calls on eight strands at once.
pub fn flow_strand(held: &mut [u32], hold: &[u32], x: &[Vec3], a: &[Vec3], g: Vec3, speed: f32, h: f32) {
    let n = held.len();
    debug_assert!(x.len() == n && a.len() == n && hold.len() == n);
    let lane0 = |v: &Vec3| {
        let mut l = L3::ZERO;
        l.set(0, *v);
        l
    };
    // Each count as lane 0 of a row.
    let rows_of = |counts: &[u32]| -> Vec<[u32; W]> {
        counts
            .iter()
            .map(|&q| {
                let mut row = [0; W];
                row[0] = q;
                row
            })
            .collect()
    };
    let (mut rows, limits) = (rows_of(held), rows_of(hold));
    let (xs, as_): (Vec<L3>, Vec<L3>) = (x.iter().map(lane0).collect(), a.iter().map(lane0).collect());
    let mut count = [0; W];
    count[0] = n;
    flow_lanes(&mut rows, &limits, &xs, &as_, &count, g, speed, h);
    for (q, r) in held.iter_mut().zip(&rows) {
        *q = r[0];
    }
}

/// [`flow_strand`] on the `W` strands of a lane group at once: lane `l` is a strand of
/// `n[l]` points, rows `0..n[l]` of `held`, `hold`, `x` and `a` (fewer than two: no flow;
/// rows past it are left alone). Each lane gets the same bits as the strand alone would: the
/// same operations in the same order, lane by lane (the f32 part then runs as vectors: one square
/// root and three divides per segment were most of the pass when it went strand by strand).
/// Inlined, so the CPU's pass compiles it for AVX2 where it runs there.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn flow_lanes(
    held: &mut [[u32; W]],
    hold: &[[u32; W]],
    x: &[L3],
    a: &[L3],
    n: &[usize; W],
    g: Vec3,
    speed: f32,
    h: f32,
) {
    debug_assert!(x.len() >= held.len() && a.len() >= held.len());
    flow_rows(held, hold, |i| x[i], |i| a[i], n, g, speed, h);
}

/// [`flow_lanes`] reading row `i`'s positions and accelerations as `x(i)` and `a(i)`, once
/// each: the CPU's pass computes the accelerations from the velocities as it goes, instead
/// of copying both into scratch first.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn flow_rows(
    held: &mut [[u32; W]],
    hold: &[[u32; W]],
    x: impl Fn(usize) -> L3,
    a: impl Fn(usize) -> L3,
    n: &[usize; W],
    g: Vec3,
    speed: f32,
    h: f32,
) {
    let rows = held.len();
    debug_assert!(n.iter().all(|&k| k <= rows) && hold.len() >= rows);
    let g_len = g.length();
    if rows < 2 || g_len <= 0.0 || speed <= 0.0 {
        return;
    }
    // Metres a step; over a segment's length (in `segment_along`), the share of the running
    // water that crosses it.
    let rate = h as f64 * speed as f64;
    // One pass with a segment's lag: segment `i`'s sends (down: `i` to `i + 1`; up: `i + 1`
    // to `i`) complete what point `i` is asked to send in all, so segment `i - 1`, whose two
    // ends' totals are then known, is applied. Sends are computed from the water at the
    // pass's start, which no applied segment has touched yet where they read it.
    // Each point's water at the pass's start, and the part of it above its hold limit that
    // may run.
    let start_run = |q: [u32; W], c: &[u32; W]| -> End { (q, std::array::from_fn(|l| running(q[l], c[l]))) };
    let (mut d_prev, mut u_prev) = ([0u64; W], [0u64; W]);
    let (mut out_prev, mut start_prev) = ([0u64; W], ([0u32; W], [0u32; W]));
    let mut start_i = start_run(held[0], &hold[0]);
    let (mut x_i, mut a_i) = (x(0), a(0));
    for i in 0..rows - 1 {
        let (start_j, x_j, a_j) = (start_run(held[i + 1], &hold[i + 1]), x(i + 1), a(i + 1));
        let (along_i, along_j) = segment_along(&x_i, &x_j, &a_i, &a_j, g, g_len);
        // Every lane computed, a lane past its strand's end sending 0 (as one skipped would:
        // its sums stay as they were), so the lanes run as vectors.
        let (mut down, mut up) = ([0.0f64; W], [0.0f64; W]);
        let (held_i, held_j) = (u32_as_f64(&start_i.1), u32_as_f64(&start_j.1));
        for l in 0..W {
            let on = i + 1 < n[l];
            let d = rate * along_i[l] as f64 * held_i[l];
            let u = rate * along_j[l] as f64 * held_j[l];
            down[l] = if on { d } else { 0.0 };
            up[l] = if on { u } else { 0.0 };
        }
        let (down, up) = (floor_nonneg_lanes(&down), floor_nonneg_lanes(&up));
        let mut out_i = [0u64; W];
        for l in 0..W {
            out_i[l] = u_prev[l].saturating_add(down[l]);
        }
        if i > 0 {
            let ends = [(out_prev, start_prev), (out_i, start_i)];
            flow_apply(held, i - 1, n, (d_prev, u_prev), ends);
        }
        (d_prev, u_prev, out_prev, start_prev, start_i) = (down, up, out_i, start_i, start_j);
        (x_i, a_i) = (x_j, a_j);
    }
    // The last segment: its far end sends nothing further.
    let ends = [(out_prev, start_prev), (u_prev, start_i)];
    flow_apply(held, rows - 2, n, (d_prev, u_prev), ends);
}

/// A point's water at the flow pass's start, per lane, and the part of it that may run.
type End = ([u32; W], [u32; W]);

/// Applies segment `i`'s sends `(down, up)` to `held` (rows `i` and `i + 1`): `ends` holds each
/// end's total asked of it and its [`End`] at the pass's start. A point asked to send more
/// than may run sends all that may, shared in proportion (rounded down, so never more); each
/// transfer is cut to the receiver's inflow bound ([`flow_inflow_bound`]) of its water at the
/// start. Where neither end is asked for more than may run (nearly always) the lanes run as
/// vectors: the sends are then whole `u32`s, and a lane past its strand's end sends 0 both
/// ways, so it moves nothing, as skipped. Each lane's sums are the same operations in the same
/// order either way.
#[inline(always)]
fn flow_apply(
    held: &mut [[u32; W]],
    i: usize,
    n: &[usize; W],
    sends: ([u64; W], [u64; W]),
    ends: [([u64; W], End); 2],
) {
    let (down, up) = sends;
    let [(out_a, (start_a, run_a)), (out_b, (start_b, run_b))] = ends;
    let over = |out: &[u64; W], run: &[u32; W]| (0..W).fold(false, |o, l| o | (out[l] > run[l] as u64));
    if !(over(&out_a, &run_a) || over(&out_b, &run_b)) {
        for l in 0..W {
            let d = (down[l] as u32).min(flow_inflow_bound(start_b[l]));
            let u = (up[l] as u32).min(flow_inflow_bound(start_a[l]));
            held[i][l] = held[i][l].wrapping_sub(d).wrapping_add(u);
            held[i + 1][l] = held[i + 1][l].wrapping_add(d).wrapping_sub(u);
        }
        return;
    }
    // In 128 bits: a segment far shorter than `speed h`, or a point flung hard, asks for up to
    // 2^64 times what may run (q <= out, so the share is at most `run`).
    let share = |q: u64, out: u64, run: u32| -> u32 {
        if out > run as u64 {
            (q as u128 * run as u128 / out as u128) as u32
        } else {
            q as u32
        }
    };
    for l in 0..W {
        if i + 1 >= n[l] {
            continue;
        }
        let d = share(down[l], out_a[l], run_a[l]).min(flow_inflow_bound(start_b[l]));
        let u = share(up[l], out_b[l], run_b[l]).min(flow_inflow_bound(start_a[l]));
        held[i][l] = held[i][l] - d + u;
        held[i + 1][l] = held[i + 1][l] + d - u;
    }
}

/// Per lane, how far the effective gravity at each end of segment `x0 -> x1` points along it,
/// over `|g|` and over the segment's length (0 where it points away; [`runs_toward`]): at the
/// first end along the unit tangent `t`, at the second along `-t`. Written out component by
/// component as glam computes `(x1 - x0).normalize_or_zero()` and `(g - a).dot(t)`, so the
/// bits are the same, and as one loop over the lanes, which the compiler runs as vectors.
#[inline(always)]
fn segment_along(x0: &L3, x1: &L3, a0: &L3, a1: &L3, g: Vec3, g_len: f32) -> (Lane, Lane) {
    let (mut wi, mut wj) = ([0.0f32; W], [0.0f32; W]);
    for l in 0..W {
        let (dx, dy, dz) = (x1.x[l] - x0.x[l], x1.y[l] - x0.y[l], x1.z[l] - x0.z[l]);
        let rcp = 1.0 / ((dx * dx) + (dy * dy) + (dz * dz)).sqrt();
        let keep = rcp.is_finite() && rcp > 0.0;
        let (tx, ty, tz) = if keep {
            (dx * rcp, dy * rcp, dz * rcp)
        } else {
            (0.0, 0.0, 0.0)
        };
        let (gx, gy, gz) = (g.x - a0.x[l], g.y - a0.y[l], g.z - a0.z[l]);
        let di = (gx * tx) + (gy * ty) + (gz * tz);
        let (hx, hy, hz) = (g.x - a1.x[l], g.y - a1.y[l], g.z - a1.z[l]);
        let dj = (hx * -tx) + (hy * -ty) + (hz * -tz);
        // A segment of no length has t = 0, so neither end sends across it.
        wi[l] = if di > 0.0 { di / g_len * rcp } else { 0.0 };
        wj[l] = if dj > 0.0 { dj / g_len * rcp } else { 0.0 };
    }
    (wi, wj)
}

/// The wind at time `t` (s): `w0` times `1 + amplitude` times the mean of three sines whose
/// frequencies (0.1-1 Hz) and phases come from `seed`. Deterministic: the same seed and time
/// give the same wind on every backend and run.
pub fn gust(w0: Vec3, amplitude: f32, seed: u32, t: f64) -> Vec3 {
    let mut state = seed ^ 0x9e37_79b9;
    let mut next = || {
        // xorshift32: the same sequence everywhere.
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f64 / u32::MAX as f64
    };
    let mut sum = 0.0f64;
    for _ in 0..3 {
        let f = 0.1 + 0.9 * next();
        let phase = std::f64::consts::TAU * next();
        sum += (std::f64::consts::TAU * f * t + phase).sin();
    }
    w0 * (1.0 + amplitude * (sum / 3.0) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strand that stands for itself keeps its bits: one quantum weighs `WATER_QUANTUM` on
    /// it, and its limits are its own.
    #[test]
    fn a_bundle_of_one_is_the_strand_itself() {
        assert_eq!(quantum_per_strand(1.0).to_bits(), (WATER_QUANTUM as f32).to_bits());
        for m in [1.0e-9f32, 3.7e-7, 1.0e-3] {
            assert_eq!(
                bundle_limits(m, 1.0, 0.3, 1.0),
                (capacity(m, 0.3), hold_limit(m, 0.3, 1.0))
            );
        }
        // A bundle past one count holds one count.
        assert_eq!(bundle_limits(1.0e-3, 10.0, 0.3, 1.0), (HELD_LIMIT, HELD_LIMIT));
        assert_eq!(
            bundle_limits(1.0e-6, 10.0, 0.3, 1.0),
            (capacity(1.0e-5, 0.3), hold_limit(1.0e-5, 0.3, 1.0))
        );
    }

    /// The row forms of the saturation and of `to_kg` give the one-point laws' bits, over
    /// capacities of zero, water over capacity and the ends of the count.
    #[test]
    fn the_row_forms_give_the_point_laws_bits() {
        let mut rng = crate::scenes::Lcg(11);
        let mut q = || match (rng.next_f32() * 6.0) as u32 {
            0 => 0,
            1 => u32::MAX,
            2 => 1 << 31,
            _ => (rng.next_f32() * 4.0e9) as u32,
        };
        for _ in 0..5000 {
            let (held, cap): ([u32; W], [u32; W]) = (std::array::from_fn(|_| q()), std::array::from_fn(|_| q()));
            let want: [u32; W] = std::array::from_fn(|l| saturation(held[l], cap[l]).to_bits());
            assert_eq!(
                saturation_lanes(&held, &cap).map(f32::to_bits),
                want,
                "{held:?} {cap:?}"
            );
            let m: Lane = std::array::from_fn(|l| 1e-9 * (1 + cap[l] % 1000) as f32);
            let b: Lane = std::array::from_fn(|l| quantum_per_strand(1.0 + (cap[l] % 7) as f32 * 0.75));
            let inv: [u32; W] = std::array::from_fn(|l| wet_inv_mass(m[l], held[l], b[l]).to_bits());
            assert_eq!(wet_inv_mass_lanes(&m, &held, &b).map(f32::to_bits), inv);
        }
    }

    /// Eight strands of different lengths flowing at once give each the same bits as it gets
    /// alone (lane 0), and rows past a strand's end are left alone.
    #[test]
    fn lanes_flow_as_each_strand_alone() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let rows = 9;
        let n = [9usize, 1, 0, 5, 9, 2, 7, 3];
        let (mut held, mut x, mut a) = (vec![[0u32; W]; rows], vec![L3::ZERO; rows], vec![L3::ZERO; rows]);
        // Hold limits from none to most of the water: some points let all of it run, some a
        // part, some none.
        let mut hold = vec![[0u32; W]; rows];
        for r in 0..rows {
            for l in 0..W {
                held[r][l] = (rnd() * 5.0e6) as u32;
                hold[r][l] = [0, 1_000_000, 4_000_000][(r + l) % 3];
                x[r].set(l, Vec3::new(rnd() * 0.01, -0.02 * r as f32, rnd() * 0.01));
                a[r].set(l, Vec3::new(rnd() - 0.5, 20.0 * (rnd() - 0.5), rnd() - 0.5));
            }
        }
        let g = Vec3::new(0.0, -9.81, 0.0);
        // 40 /s over the 2 cm segments.
        let (h, speed) = (1.0 / 60.0, 40.0 * FLOW_LENGTH);
        let before = held.clone();
        flow_lanes(&mut held, &hold, &x, &a, &n, g, speed, h);
        let mut moved = 0;
        for l in 0..W {
            let mut alone: Vec<u32> = before[..n[l]].iter().map(|r| r[l]).collect();
            let xs: Vec<Vec3> = x[..n[l]].iter().map(|r| r.get(l)).collect();
            let as_: Vec<Vec3> = a[..n[l]].iter().map(|r| r.get(l)).collect();
            let limits: Vec<u32> = hold[..n[l]].iter().map(|r| r[l]).collect();
            flow_strand(&mut alone, &limits, &xs, &as_, g, speed, h);
            for r in 0..rows {
                let want = if r < n[l] { alone[r] } else { before[r][l] };
                assert_eq!(held[r][l], want, "lane {l} row {r}");
                moved += (held[r][l] != before[r][l]) as usize;
            }
        }
        assert!(moved > 10, "water moved at {moved} points");
    }

    /// A row dries as its points do one by one, with every lane's rate small (the vector
    /// series in single precision), with rates past it (double precision) and with one lane's
    /// far past the series (each lane then by `one_minus_exp_neg`).
    #[test]
    fn lanes_dry_as_each_point_alone() {
        let held = [0u32, 1, 7, 1000, 123_456, 9_999_999, 1 << 30, u32::MAX];
        for k in [
            [1e-3f32, 5e-4, 0.02, 0.0, 8e-4, 1e-3, 3e-3, 0.05],
            [1e-3f32, 5e-4, 0.02, -0.0, 8e-4, 1e-3, -3e-3, 0.05],
            [0.5f32, 1.0, 2.0, 0.25, 3.0, 1.5, 0.75, 0.0],
            [0.5f32, 1.0, 200.0, 0.25, 3.0, 1.5, 0.75, 0.0],
        ] {
            let e = evaporate_lanes(&held, &k, 1.0 / 60.0);
            for l in 0..W {
                assert_eq!(e[l], evaporate(held[l], k[l], 1.0 / 60.0), "lane {l}, rates {k:?}");
            }
        }
    }

    /// A step's drying in single precision is within two quanta of the double-precision law
    /// for any count, and the same to the quantum for counts a point holds at the defaults.
    #[test]
    fn single_precision_drying_keeps_the_law() {
        let mut x = 1e-9f32;
        while small(x) {
            for held in [1u32, 999, 123_456, 30_000_000, 1 << 31, u32::MAX] {
                let fast = evaporate(held, x, 1.0) as i64;
                let exact = evaporated_part(held, one_minus_exp_neg(x as f64)) as i64;
                let tol = if held <= 30_000_000 { 1 } else { 2 };
                assert!((fast - exact).abs() <= tol, "x {x}, held {held}: {fast} vs {exact}");
            }
            x *= 1.37;
        }
    }

    /// At least one part in twenty of the capacity, rounded up, and never a dry point.
    #[test]
    fn a_point_bridges_from_five_per_cent_of_its_capacity() {
        assert_eq!(BRIDGE_MIN_PARTS, 20);
        assert!(!can_bridge(0, 1000) && !can_bridge(49, 1000) && can_bridge(50, 1000));
        assert!(!can_bridge(5, 101) && can_bridge(6, 101));
        assert!(can_bridge(1, 20) && can_bridge(1, 1) && can_bridge(1, 0) && !can_bridge(0, 0));
        let big = 1u32 << 31;
        assert!(!can_bridge(big / 20, big) && can_bridge(big / 20 + 1, big));
        // The multiply is the divide's test (what the GPU's bridges.wgsl computes), up to
        // the largest counts.
        let mut rng = crate::scenes::Lcg(7);
        let edges = [
            0,
            1,
            19,
            20,
            21,
            39,
            40,
            41,
            1 << 31,
            u32::MAX / 20,
            u32::MAX - 1,
            u32::MAX,
        ];
        for k in 0..200_000u32 {
            let (h, c) = if k < 144 {
                (edges[k as usize % 12], edges[k as usize / 12])
            } else {
                let c = (rng.next_f32() * 4.0e9) as u32;
                (((rng.next_f32() * 0.1) * c as f32) as u32 + k % 3, c)
            };
            assert_eq!(
                can_bridge(h, c),
                h > 0 && h >= c.div_ceil(BRIDGE_MIN_PARTS),
                "{h} of {c}"
            );
        }
    }

    /// The series agrees with `exp_m1` to a few units in the last place, and the quanta it
    /// rounds to differ at most by one.
    #[test]
    fn one_minus_exp_neg_agrees_with_exp_m1() {
        let mut x = 1e-12f64;
        while x < 0.1 {
            let (a, b) = (one_minus_exp_neg(x), -(-x).exp_m1());
            assert!((a - b).abs() <= 4.0 * f64::EPSILON * b, "{x}: {a} vs {b}");
            for held in [1u32, 999, 123_456, 3_000_000_000] {
                let (ea, eb) = ((held as f64 * a).round(), (held as f64 * b).round());
                assert!((ea - eb).abs() <= 1.0, "{x} {held}");
            }
            x *= 1.07;
        }
    }
}
