//! The held water's per-point laws over a run of rows, each written once and called both by
//! the passes that sweep the whole groom and by the pass after the substeps, which runs them
//! block by block while the block is in cache (`cpu/settle.rs`). Every function is
//! `#[inline(always)]`, so it compiles for AVX2 inside a caller run through
//! `run_avx2_or_base`. A run starts at a block's first row, so row `k` of it is point
//! `k % rows` of its strands.

use super::layout::{Layout, ParamRow, StateRow};
use crate::physics::lanes::{Lane, L3, W};
use crate::physics::wet;
use glam::Vec3;

/// A row's dry values that its wet parameters are computed from, kept together in one cache
/// line: the refresh then reads one compact record a row, not two cache lines of the
/// layout's 224-byte parameter row besides the masses.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(64))]
pub struct DryRow {
    /// Dry mass per point, kg; infinite where the layout's inverse mass is 0 (pinned points,
    /// padding lanes), so `1 / (mass + water)` is the layout's inverse mass, bit for bit, at
    /// every point without water (the layout's is `1 / mass` in single precision) and 0 at
    /// every point that does not move.
    pub mass: Lane,
    /// The layout's bend stiffness, N/m.
    pub bend_k: Lane,
}

/// A quantum's water on a point that stands for its own strand only.
const ONE_STRAND: Lane = [wet::WATER_QUANTUM as f32; W];

/// What the wet parameters are computed from: the rows' dry records and capacities, and the
/// model's limpness.
pub struct ParamSource<'a> {
    /// Rows per block.
    pub rows: usize,
    /// Each row's dry record.
    pub dry: &'a [DryRow],
    /// Each row's water per quantum and strand, kg (empty: `WATER_QUANTUM` everywhere).
    pub quantum: &'a [Lane],
    pub capacity: &'a [[u32; W]],
    /// The rows' hold limits.
    pub hold: &'a [[u32; W]],
    /// Whether bend stiffness falls with saturation, and the saturated ratio.
    pub limp: bool,
    pub ratio: f32,
}

/// `wet_params` on rows `r0..` (`water` holds exactly those rows' water, `out` and
/// `was_wet` their parameters and flags; `sat(k)` is row `k`'s saturations, unclamped, as
/// `wet::saturation` gives them): each free point's inverse mass becomes `1 / (dry + water)`
/// and, when limp, each bend spring's stiffness is scaled by `wet::bend_scale` of the mean
/// saturation of its two ends. A row that was and is dry is left as it is (it holds the
/// layout's values); one that dries gets them back bit for bit.
#[inline(always)]
pub fn refresh_rows(
    src: &ParamSource,
    r0: usize,
    water: &[[u32; W]],
    sat: impl Fn(usize) -> Lane,
    out: &mut [ParamRow],
    was_wet: &mut [bool],
) {
    let (rows, limp) = (src.rows, src.limp);
    for (k, (row, was_wet)) in out.iter_mut().zip(was_wet).enumerate() {
        let (r, i) = (r0 + k, (r0 + k) % rows);
        let holds = |k: usize| water[k] != [0; W];
        let bends = limp && i + 2 < rows;
        let wet = holds(k) || (bends && holds(k + 2));
        if !wet && !*was_wet {
            continue; // still the layout's values
        }
        *was_wet = wet;
        // Each lane computed, then chosen (a branch per point was most of the pass).
        let dry = &src.dry[r];
        let quantum = src.quantum.get(r).unwrap_or(&ONE_STRAND);
        row.inv_mass = wet::wet_inv_mass_lanes(&dry.mass, &water[k], quantum);
        if bends {
            let (s_a, s_b) = (sat(k), sat(k + 2));
            for l in 0..W {
                let k_dry = dry.bend_k[l];
                let wet_k = k_dry * wet::bend_scale(0.5 * (s_a[l] + s_b[l]), src.ratio);
                row.bend.k[l] = if s_a[l] + s_b[l] == 0.0 { k_dry } else { wet_k };
            }
        }
    }
}

/// The drying law's inputs: wind, time constant and reference air speed.
#[derive(Clone, Copy)]
pub struct DryLaw {
    pub wind: Vec3,
    pub tau: f32,
    pub u_ref: f32,
    pub dt: f32,
}

/// Pass `dry` on a run of rows (`state` from the same row on): each point loses
/// `held (1 - e^(-k dt))` to the nearest quantum, `k` from the air speed past it. Returns
/// the quanta lost (a sum of integers: the same in any order).
#[inline(always)]
pub fn dry_rows(water: &mut [[u32; W]], state: &[StateRow], law: DryLaw) -> u64 {
    let DryLaw { wind, tau, u_ref, dt } = law;
    let mut lost = 0;
    for (w, r) in water.iter_mut().zip(state) {
        if w.iter().all(|&q| q == 0) {
            continue;
        }
        // The row's rates as one vector: `(wind - v).length()` component by component as
        // glam computes it, so the bits are the same.
        let mut u = [0.0f32; W];
        for (l, u) in u.iter_mut().enumerate() {
            let (ux, uy, uz) = (wind.x - r.v.x[l], wind.y - r.v.y[l], wind.z - r.v.z[l]);
            *u = ((ux * ux) + (uy * uy) + (uz * uz)).sqrt();
        }
        let k = wet::evaporation_rate_lanes(&u, tau, u_ref);
        let e = wet::evaporate_lanes(w, &k, dt);
        for l in 0..W {
            w[l] -= e[l];
            lost += e[l] as u64;
        }
    }
    lost
}

/// Each point's wetness, its water over its hold limit at most 1 (`capacity` and `hold` from
/// the same row on); returns whether any point holds water. With `keep`, each row's
/// saturations (water over capacity, unclamped) are also kept there (for [`refresh_rows`]).
#[inline(always)]
pub fn saturation_rows(
    water: &[[u32; W]],
    capacity: &[[u32; W]],
    hold: &[[u32; W]],
    out: &mut [Lane],
    keep: Option<&mut Vec<Lane>>,
) -> bool {
    let mut held = false;
    let mut keep = keep;
    if let Some(k) = keep.as_deref_mut() {
        k.clear();
    }
    for (((out, w), c), h) in out.iter_mut().zip(water).zip(capacity).zip(hold) {
        held |= *w != [0; W];
        let shown = wet::saturation_lanes(w, h);
        for l in 0..W {
            out[l] = shown[l].min(1.0);
        }
        if let Some(k) = keep.as_deref_mut() {
            k.push(wet::saturation_lanes(w, c));
        }
    }
    held
}

/// Per row, a bit per lane that takes part in the liquid bridges: a free point
/// (`free`, from the same row on) holding water enough to bridge ([`wet::can_bridge`]).
#[inline(always)]
pub fn bridge_marks(water: &[[u32; W]], capacity: &[[u32; W]], free: &[u8], out: &mut [u8]) {
    for (((m, w), c), &f) in out.iter_mut().zip(water).zip(capacity).zip(free) {
        *m = pack_bits(std::array::from_fn(|l| wet::can_bridge(w[l], c[l]))) & f;
    }
}

/// Per lane of a block (`water` its rows, `hold` from its first row on), whether some
/// point holds a drop's excess over its hold limit: which strands the drip pass visits.
#[inline(always)]
pub fn drip_lanes(water: &[[u32; W]], hold: &[[u32; W]], min_drop: u32) -> u8 {
    let mut m = 0u8;
    for (w, c) in water.iter().zip(hold) {
        m |= pack_bits(std::array::from_fn(|l| wet::drip(w[l], c[l], min_drop) > 0));
    }
    m
}

/// Lane `l`'s flag as bit `l`.
#[inline(always)]
fn pack_bits(b: [bool; W]) -> u8 {
    let mut m = 0u8;
    for (l, &b) in b.iter().enumerate() {
        m |= (b as u8) << l;
    }
    m
}

/// What the passes over one block work in: its saturations (kept by [`saturation_rows`] for
/// [`refresh_rows`]).
#[derive(Debug, Default)]
pub struct BlockScratch {
    pub sat: Vec<Lane>,
}

impl BlockScratch {
    /// Room for a block of `rows` rows.
    pub fn with_rows(rows: usize) -> BlockScratch {
        BlockScratch {
            sat: Vec::with_capacity(rows),
        }
    }
}

/// Pass `flow` on block `b` (`water` its rows; `hold`, `state` and `v0` from its first row
/// on): held water above each point's hold limit runs along each strand toward where gravity
/// minus the point's acceleration over the step points (`wet::flow_rows`, the block's eight
/// strands at once; `speed` is `HeldWater::flow_speed`). A block with no water above a hold
/// limit is left alone (nearly every wet block: the water the hair holds does not run).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn flow_block(
    lay: &Layout,
    b: usize,
    water: &mut [[u32; W]],
    hold: &[[u32; W]],
    state: &[StateRow],
    v0: &[L3],
    g: Vec3,
    speed: f32,
    dt: f32,
) {
    let hold = &hold[..water.len()];
    // A fold, not `any`: no branch a lane.
    let runs = water
        .iter()
        .zip(hold)
        .fold(false, |r, (w, c)| (0..W).fold(r, |r, l| r | (w[l] > c[l])));
    if !runs {
        return;
    }
    // Each lane's points: its real rows, which are the block's first (read from the block's
    // own marks: looking each strand's length up was a cache miss per lane).
    let real = &lay.real_lanes[b * water.len()..(b + 1) * water.len()];
    let n: [usize; W] = std::array::from_fn(|l| real.iter().map(|&m| ((m >> l) & 1) as usize).sum());
    let (state, v0) = (&state[..water.len()], &v0[..water.len()]);
    // The closures marked inline: left calls, they ran compiled without AVX2.
    wet::flow_rows(
        water,
        hold,
        #[inline(always)]
        |i| state[i].x,
        #[inline(always)]
        |i| {
            let (v, v0) = (&state[i].v, &v0[i]);
            let mut a = L3::ZERO;
            for l in 0..W {
                a.x[l] = (v.x[l] - v0.x[l]) / dt;
                a.y[l] = (v.y[l] - v0.y[l]) / dt;
                a.z[l] = (v.z[l] - v0.z[l]) / dt;
            }
            a
        },
        &n,
        g,
        speed,
        dt,
    );
}
