//! BDF2 (the two-step backward differentiation formula) as a backward Euler step from a blended
//! start, so both backends run it on their implicit Euler solvers unchanged.
//!
//! With steps `h` (this one) and `h_prev` (the one before), ratio `ω = h / h_prev`, variable-step
//! BDF2 reads, for positions and likewise for velocities,
//!
//! `x₁ - a x₀ + b x₋₁ = ĥ v₁`,  `a = (1+ω)² / (1+2ω)`, `b = ω² / (1+2ω)`, `ĥ = h (1+ω) / (1+2ω)`
//!
//! (at `ω = 1`: `4/3`, `1/3`, `2h/3`). Writing `x̂ = a x₀ - b x₋₁` and `v̂ = a v₀ - b v₋₁`, this is
//! backward Euler of step `ĥ` from `(x̂, v̂)`: `x₁ = x̂ + ĥ v₁`, `v₁ = v̂ + ĥ a(x₁, v₁)`. So a BDF2
//! step blends the start, then runs the implicit Euler solve (its incremental potential, Newton
//! iterations, line search and damping about the start's spring vectors, all at `x̂` and `ĥ`).
//! Second order in the springs and in the air drag (both are in the solve), and L-stable (stiff
//! modes are damped, never amplified); the forces taken explicitly (adhesion, cohesion) are
//! taken at `x₀` as in backward Euler, so they stay first order.
//!
//! **When the history is kept.** The recurrence's second root is `b`: a change between the two
//! starts that is not on the smooth path is multiplied by `b` each step. At a steady step
//! `b = 1/3` and such changes die out; a single jump of the frame time (a hitch: `ω = 3`, `b = 9/7`)
//! grows them once, which is harmless, but steps that keep growing past `ω = 1 + √2` (`b > 1`)
//! would make them grow without bound (the known zero-stability limit of variable-step BDF2).
//! [`Bdf2Clock`] tracks the largest growth `b` can have given any error since the last restart,
//! and takes a backward Euler step instead (restarting the history) when it would pass
//! [`MAX_GROWTH`]; the first step, and the first after a reset, are backward Euler steps too.
//! Restarting at every jump above 2x instead cost a hitch from 1/60 to 1/20 s about 3x in
//! error on the dry patch (measured in `tests/integrators.rs`).

use super::implicit::{start_of_state, LaneD};
use super::lanes::{Lane, StateRow, L3, W};

/// Largest growth of a stray difference between the two starts that [`Bdf2Clock`] lets the
/// history carry (the product of the blends' `b` since an error could enter); past it, a
/// backward Euler step restarts. Admits any single jump of up to `2 + √6 ≈ 4.4` times the step.
pub const MAX_GROWTH: f64 = 2.0;

/// One BDF2 step's blend: the start is `a x₀ - b x₋₁` (and the same for velocities), and the
/// implicit Euler solve then takes step `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bdf2Blend {
    /// Weight of this start, `(1+ω)² / (1+2ω)`, which is `1 + b` (the blend is taken as
    /// `x₀ + b (x₀ - x₋₁)`: see [`start_rows`]).
    pub a: f32,
    /// Weight of the start before, `ω² / (1+2ω)` (0: backward Euler).
    pub b: f32,
    /// The solve's step, `h (1+ω) / (1+2ω)`, s.
    pub h: f32,
}

impl Bdf2Blend {
    /// The blend for step `h` after a step of `h_prev`, or `None` when there is no history
    /// (`h_prev` is 0). Whether the history may be used is [`Bdf2Clock`]'s call.
    pub fn new(h: f32, h_prev: f32) -> Option<Bdf2Blend> {
        // Reckoned in f64 and rounded once, so both backends use the same three numbers.
        let (h, hp) = (h as f64, h_prev as f64);
        // (A NaN step has no history either.)
        if !(hp > 0.0 && h > 0.0) {
            return None;
        }
        let w = h / hp;
        let den = 1.0 + 2.0 * w;
        Some(Bdf2Blend {
            a: ((1.0 + w) * (1.0 + w) / den) as f32,
            b: (w * w / den) as f32,
            h: (h * (1.0 + w) / den) as f32,
        })
    }

    /// Backward Euler's "blend" for step `h`: the start as it is.
    pub fn euler(h: f32) -> Bdf2Blend {
        Bdf2Blend { a: 1.0, b: 0.0, h }
    }
}

/// Where a BDF2 run stands between frames: the last substep and the growth a stray
/// difference between the starts may have had since the last restart. Both backends hold one
/// and ask it for each frame's blends, so they pick the same ones.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Bdf2Clock {
    /// The last substep, s (0: no history, after creation or a reset).
    h_prev: f32,
    /// The largest product of `b` over the steps since any of them (at least 1 means "an error
    /// entering now"), reckoned in f64.
    growth: f64,
}

impl Bdf2Clock {
    /// The blends of a frame of `substeps` equal substeps `h`: the first substep's (a backward
    /// Euler restart when there is no history or it would grow past [`MAX_GROWTH`]) and the
    /// others' (steady BDF2); advances the clock past the frame.
    pub fn frame(&mut self, h: f32, substeps: u32) -> (Bdf2Blend, Bdf2Blend) {
        let steady = Bdf2Blend::new(h, h).unwrap_or(Bdf2Blend::euler(h));
        let first = match Bdf2Blend::new(h, self.h_prev) {
            Some(b) if b.b as f64 * self.growth.max(1.0) <= MAX_GROWTH => {
                self.growth = b.b as f64 * self.growth.max(1.0);
                b
            }
            _ => {
                self.growth = 0.0;
                Bdf2Blend::euler(h)
            }
        };
        for _ in 1..substeps.min(8) {
            // (1/3)^7 already takes any growth below 1; more substeps change nothing.
            self.growth = steady.b as f64 * self.growth.max(1.0);
        }
        self.h_prev = h;
        (first, steady)
    }
}

/// BDF2's history of one row of `W` points, kept between substeps (CPU backend).
///
/// Why a displacement and a rounding, not the earlier positions: in f32, `x₀ - x₋₁` is the
/// difference of two rounded positions near 0.2 m, so it carries an error of a few 1e-9 m in a
/// substep's motion of about as much, and the rounding of each new position is lost for good;
/// the blend feeds both forward every substep, and BDF2's error on the dry patch rose with the
/// substeps past 32 (2.9e-6 m at 128, where the method's own is below 1e-8 m). Kept from the
/// f64 solve as below, the error there falls to about 6e-9 m; with the velocities' rounding
/// kept too, to about 2e-9 m from 128 substeps to 1,024
/// (`tests/integrators.rs` `bdf2_converges_past_the_f32_rounding`).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct Bdf2Row {
    /// `x₀ - x₋₁`: the last substep's displacement, from the solve's f64 positions (and the
    /// collide pass's pushes), rounded once.
    pub dx: L3,
    /// `v₋₁`: the velocities at the last substep's start.
    pub v: L3,
    /// What rounding the solve's f64 positions to the f32 state took off: the start of the
    /// next substep is the state plus this (0 for points a push moved).
    pub rounding: L3,
    /// What rounding the solve's f64 velocities to the f32 state took off, restored the same
    /// way (0 for points a push moved). Without it the velocities' roundings walk the strands
    /// off at random, and BDF2's error on the dry patch rose again past 128 substeps: 6.7e-9,
    /// 1.9e-8, 2.9e-8 and 3.9e-8 m at 128, 256, 512 and 1,024 (with it 3.0e-9, 2.1e-9, 2.4e-9
    /// and 2.5e-9 m: the f32 positions' own resolution).
    pub vrounding: L3,
}

/// The starts of a block's rows in f64, per DOF (`3 i + c`): `x`, the blended start
/// `x̂ = x₀ + b Δx` (`x₀` each position with its rounding restored), and `v`,
/// `v̂ = v₀ + b (v₀ - v₋₁)` (`v₀` each velocity with its rounding restored). With `b = 0` (a
/// restart) the start is the state as it is, whatever the history holds.
///
/// Taken as `x₀ + b (x₀ - x₋₁)` (`a = 1 + b`): in f32 the rounded `a` and `b` do not differ by
/// exactly 1, and `a x₀ - b x₋₁` scaled every position by that error each step (1.4e-5 m after
/// 7,680 steps on the dry patch, past implicit Euler's).
#[inline(always)]
pub fn start_rows(state: &[StateRow], history: &[Bdf2Row], b: f32, x: &mut [LaneD], v: &mut [LaneD]) {
    if b == 0.0 {
        return start_of_state(state, x, v);
    }
    let bd = b as f64;
    for (i, (st, h)) in state.iter().zip(history).enumerate() {
        let (now, vel) = (coords(&st.x), coords(&st.v));
        let (r, dx, vp, vr) = (coords(&h.rounding), coords(&h.dx), coords(&h.v), coords(&h.vrounding));
        for c in 0..3 {
            let k = 3 * i + c;
            start_coord(
                &mut x[k],
                &mut v[k],
                (now[c], vel[c]),
                (r[c], vr[c]),
                (dx[c], vp[c]),
                bd,
            );
        }
    }
}

/// One coordinate of [`start_rows`] for the `W` lanes of a row (kept history).
#[inline(always)]
fn start_coord(
    x: &mut LaneD,
    v: &mut LaneD,
    (now, vel): (&Lane, &Lane),
    (r, vr): (&Lane, &Lane),
    (dx, vp): (&Lane, &Lane),
    b: f64,
) {
    for l in 0..W {
        let (p, q) = (now[l] as f64 + r[l] as f64, vel[l] as f64 + vr[l] as f64);
        x[l] = p + b * dx[l] as f64;
        v[l] = q + b * (q - vp[l] as f64);
    }
}

/// Keeps the history of a block's rows for the next substep, after a solve with blend `b` took
/// them from `state` to `x1` (f64, before they are rounded into the state; the history still
/// holds the last substep's): the displacement `x1 - x₀` (`x₀` as [`start_rows`] took it),
/// the velocities `v₀`, and what rounding `x1` to f32 takes off.
#[inline(always)]
pub fn keep_rows(history: &mut [Bdf2Row], state: &[StateRow], b: f32, x1: &[LaneD]) {
    // A restart's start ignored the history's rounding.
    let kept = if b == 0.0 { 0.0 } else { 1.0 };
    for (i, (h, st)) in history.iter_mut().zip(state).enumerate() {
        h.v = st.v;
        let now = coords(&st.x);
        let (dx, r) = (&mut h.dx, &mut h.rounding);
        for (c, (dx, r)) in [(&mut dx.x, &mut r.x), (&mut dx.y, &mut r.y), (&mut dx.z, &mut r.z)]
            .into_iter()
            .enumerate()
        {
            keep_coord(dx, r, now[c], &x1[3 * i + c], kept);
        }
    }
}

/// Keeps what rounding the solve's velocities to the f32 state took off, once the state holds
/// them: the solve's velocity is `(x1 - x̂) / ĥ` in f64, `x1` and `start` (`x̂`) its positions.
#[inline(always)]
pub fn keep_velocity_rounding(history: &mut [Bdf2Row], state: &[StateRow], x1: &[LaneD], start: &[LaneD], inv_h: f64) {
    for (i, (h, st)) in history.iter_mut().zip(state).enumerate() {
        let vr = &mut h.vrounding;
        for (c, (vr, v)) in [(&mut vr.x, &st.v.x), (&mut vr.y, &st.v.y), (&mut vr.z, &st.v.z)]
            .into_iter()
            .enumerate()
        {
            let (x1, s) = (&x1[3 * i + c], &start[3 * i + c]);
            for l in 0..W {
                vr[l] = ((x1[l] - s[l]) * inv_h - v[l] as f64) as f32;
            }
        }
    }
}

/// One coordinate of [`keep_rows`] for the `W` lanes of a row.
#[inline(always)]
fn keep_coord(dx: &mut Lane, r: &mut Lane, now: &Lane, x1: &LaneD, kept: f64) {
    for l in 0..W {
        let x0 = now[l] as f64 + kept * r[l] as f64;
        dx[l] = (x1[l] - x0) as f32;
        r[l] = (x1[l] - (x1[l] as f32) as f64) as f32;
    }
}

/// The three coordinates' lanes of `v`.
#[inline(always)]
fn coords(v: &L3) -> [&Lane; 3] {
    [&v.x, &v.y, &v.z]
}

/// Where a BDF2 step takes its explicit forces (eq. 2's adhesion, pass `adhesion`): at
/// `x₀ + h v₀` (h the substep), which is the step's end to `O(h²)`, not at its start `x₀`.
///
/// Why: BDF2 with a force taken at `x₀` is unstable for any oscillation that force drives, at
/// every step size. A hair point held by a droplet is such an oscillator: for `x'' = -ω² x`
/// taken at `x₀`, the recurrence's energy grows 6.6x over 30 periods at `ω h = 0.01` and 280x
/// at 0.03 (docs/METHOD.md §3). On the wet patch BDF2's runs sat 2.7e-5 m from the
/// references' mean at 512 substeps and 1.7e-5 at 1,024, where implicit Euler's came within
/// chance (the report's ensemble of each integrator). Taken at `x₀ + h v₀`, the oscillation is
/// stable up to `ω h ≈ 1.5` and mildly damped (0.3% of its energy over 30 periods at
/// `ω h = 0.03`, as the solve's own start iterate `x̂ + ĥ v̂` would give), and since the point
/// is off the step's end by `O(h²)`, the forces stay second order. It needs no history, so
/// both backends take the same point. Implicit Euler keeps `x₀`: there the explicit forces
/// enter as in symplectic Euler, stable to `ω h = 2`.
#[inline(always)]
pub fn explicit_point(st: &StateRow, h: f32) -> L3 {
    debug_assert!(h > 0.0, "explicit_point is BDF2's: see explicit_lead");
    let mut out = st.x;
    for (o, v) in [(&mut out.x, &st.v.x), (&mut out.y, &st.v.y), (&mut out.z, &st.v.z)] {
        for l in 0..W {
            o[l] += h * v[l];
        }
    }
    out
}

/// How far ahead, in seconds, `integrator` takes its explicit forces (adhesion, cohesion) in
/// a substep of `h`: BDF2 at `x + h v` ([`explicit_point`]), the others at `x` (0). The one
/// place the CPU decides it; the GPU's `explicit_point` in hair.wgsl reads the same rule from
/// its `BDF2` constant.
#[inline(always)]
pub fn explicit_lead(integrator: crate::params::Integrator, h: f32) -> f32 {
    if integrator == crate::params::Integrator::BDF2 {
        h
    } else {
        0.0
    }
}

/// The history follows a push after the solve (the collide pass moved a row from `before` to
/// `after`): a moved lane's displacement gains the push, less the rounding its old place had,
/// and its new place is exact; lanes left alone keep theirs.
#[inline(always)]
pub fn keep_push(history: &mut Bdf2Row, before: &L3, after: &L3) {
    let (d, r, vr) = (&mut history.dx, &mut history.rounding, &mut history.vrounding);
    for (dx, rx, vx, b, a) in [
        (&mut d.x, &mut r.x, &mut vr.x, &before.x, &after.x),
        (&mut d.y, &mut r.y, &mut vr.y, &before.y, &after.y),
        (&mut d.z, &mut r.z, &mut vr.z, &before.z, &after.z),
    ] {
        for l in 0..W {
            // Branch-free (every BDF2 row of a scene with colliders passes here each substep):
            // 1 where the push moved it (its velocity changed with it).
            let moved = (a[l] != b[l]) as u32 as f32;
            dx[l] += moved * ((a[l] - b[l]) - rx[l]);
            rx[l] *= 1.0 - moved;
            vx[l] *= 1.0 - moved;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_steps_give_the_textbook_coefficients() {
        let b = Bdf2Blend::new(0.01, 0.01).unwrap();
        assert!((b.a - 4.0 / 3.0).abs() < 1e-7 && (b.b - 1.0 / 3.0).abs() < 1e-7);
        assert!((b.h - 0.01 * 2.0 / 3.0).abs() < 1e-9);
    }

    #[test]
    fn a_missing_history_restarts() {
        assert_eq!(Bdf2Blend::new(0.01, 0.0), None);
        let mut c = Bdf2Clock::default();
        assert_eq!(
            c.frame(0.01, 2),
            (Bdf2Blend::euler(0.01), Bdf2Blend::new(0.01, 0.01).unwrap())
        );
        assert_eq!(c.frame(0.01, 2).0, Bdf2Blend::new(0.01, 0.01).unwrap());
    }

    /// One hitch of 3x keeps the history; frames that keep tripling restart on the third (the
    /// growth 9/7 per step passes 2), and a steady run in between forgets the growth.
    #[test]
    fn jumps_keep_the_history_until_the_growth_passes_the_limit() {
        let mut c = Bdf2Clock::default();
        c.frame(0.01, 1);
        assert!(c.frame(0.03, 1).0.b > 1.0);
        c.frame(0.03, 4);
        assert!(
            c.frame(0.09, 1).0.b > 1.0,
            "a single 3x jump after a steady run keeps it"
        );
        assert!(c.frame(0.27, 1).0.b > 1.0, "growth 81/49 < 2");
        assert_eq!(c.frame(0.81, 1).0, Bdf2Blend::euler(0.81), "growth 2.1 > 2 restarts");
        assert_eq!(c.frame(5.0, 1).0, Bdf2Blend::euler(5.0), "a 6x jump alone passes 2");
    }

    /// A kept row starts the next substep with the f64 solve's velocity, not the f32 state's.
    #[test]
    fn the_history_restores_the_velocities_rounding() {
        let (start, inv_h) = ([[0.2f64; W]; 3], 3000.0);
        let x1: [LaneD; 3] = [[0.2 + 1e-4 / 3.0; W], [0.2 - 2e-5 / 7.0; W], [0.2; W]];
        let v64 = |c: usize| (x1[c][0] - start[c][0]) * inv_h;
        let mut row = StateRow::default();
        for l in 0..W {
            row.v
                .set(l, glam::Vec3::new(v64(0) as f32, v64(1) as f32, v64(2) as f32));
        }
        let state = [row];
        let mut hist = [Bdf2Row::default()];
        keep_velocity_rounding(&mut hist, &state, &x1, &start, inv_h);
        let (mut x, mut v) = ([[0.0; W]; 3], [[0.0; W]; 3]);
        // With v₋₁ = 0 the blended start is (1 + b) v₀.
        start_rows(&state, &hist, 0.25, &mut x, &mut v);
        for c in 0..3 {
            let v0 = v[c][5] / 1.25;
            assert!((v0 - v64(c)).abs() < 1e-15, "{c}: {v0} vs {}", v64(c));
        }
        assert_ne!(v64(0), (v64(0) as f32) as f64, "the case must round");
    }

    /// A kept row starts the next substep where the f64 solve left it, not where the f32 state
    /// rounded it, and a push moves the start exactly to the pushed place.
    #[test]
    fn the_history_restores_what_rounding_took() {
        let splat = |v: f32| L3 {
            x: [v; W],
            y: [v; W],
            z: [v; W],
        };
        let now = [StateRow {
            x: splat(0.2),
            v: splat(0.5),
        }];
        let x0 = [[0.2f32 as f64; W]; 3];
        let x1: [LaneD; 3] = [[0.2 + 3.3e-9; W], [0.2 - 1.7e-9; W], [0.2 + 1e-12; W]];
        let mut hist = [Bdf2Row::default()];
        keep_rows(&mut hist, &now, 0.0, &x1);
        let mut next = now;
        for l in 0..W {
            next[0]
                .x
                .set(l, glam::Vec3::new(x1[0][l] as f32, x1[1][l] as f32, x1[2][l] as f32));
        }
        // The start with b = 0 is x₀ itself: where the solve left the row, rounding restored
        // only when the history is kept (b > 0).
        let start = |state: &[StateRow], hist: &[Bdf2Row], b: f32| {
            let (mut s, mut v) = ([[0.0; W]; 3], [[0.0; W]; 3]);
            start_rows(state, hist, b, &mut s, &mut v);
            s
        };
        let s = start(&next, &hist, 0.25);
        for c in 0..3 {
            let s0 = s[c][3] - 0.25 * hist[0].dx.get(3)[c] as f64;
            assert!((s0 - x1[c][3]).abs() < 1e-16, "{c}: {s0} vs {}", x1[c][3]);
            assert!((s[c][3] - (x1[c][3] + 0.25 * (x1[c][3] - x0[c][3]))).abs() < 1e-16);
            assert_eq!(start(&next, &hist, 0.0)[c][3], next[0].x.get(3)[c] as f64);
        }
        // A push to 0.3 in lane 1: that lane's start is the pushed place; lane 0's is kept.
        let before = next[0].x;
        next[0].x.set(1, glam::Vec3::splat(0.3));
        keep_push(&mut hist[0], &before, &next[0].x);
        let p = start(&next, &hist, 0.25);
        for c in 0..3 {
            let moved = 0.3f32 as f64 - x0[c][1];
            assert!((p[c][1] - (0.3f32 as f64 + 0.25 * moved)).abs() < 1e-9);
            assert_eq!(p[c][0], s[c][0]);
        }
    }

    /// The blend is exact for a quadratic path: x(t) = t², steps h then h ω: BDF2 is exact on
    /// polynomials of degree 2, so x̂ + ĥ x'(t₁) = x(t₁).
    #[test]
    fn variable_steps_are_exact_on_a_quadratic() {
        for (hp, h) in [(0.01f64, 0.01f64), (0.01, 0.015), (0.01, 0.006)] {
            let b = Bdf2Blend::new(h as f32, hp as f32).unwrap();
            let (t0, t1) = (hp, hp + h);
            let xhat = b.a as f64 * t0 * t0 - b.b as f64 * 0.0;
            let x1 = xhat + b.h as f64 * 2.0 * t1;
            assert!((x1 - t1 * t1).abs() < 1e-8, "{hp} {h}: {x1} vs {}", t1 * t1);
        }
    }
}
