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

use super::lanes::{StateRow, W};

/// Largest growth of a stray difference between the two starts that [`Bdf2Clock`] lets the
/// history carry (the product of the blends' `b` since an error could enter); past it, a
/// backward Euler step restarts. Admits any single jump of up to `2 + √6 ≈ 4.4` times the step.
pub const MAX_GROWTH: f64 = 2.0;

/// One BDF2 step's blend: the start is `a x₀ - b x₋₁` (and the same for velocities), and the
/// implicit Euler solve then takes step `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bdf2Blend {
    /// Weight of this start, `(1+ω)² / (1+2ω)`, which is `1 + b` (the blend is taken as
    /// `x₀ + b (x₀ - x₋₁)`: see [`blend_rows`]).
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

/// Replaces each row by its blended start `a x₀ - b x₋₁`, `a v₀ - b v₋₁` (`history` holds
/// `x₋₁, v₋₁`) and keeps the rows as they were in `history` for the next step. With `b = 0` the
/// rows stay as they are (and are still kept).
///
/// Computed as `x₀ + b (x₀ - x₋₁)` (`a = 1 + b`): in f32 the rounded `a` and `b` do not differ
/// by exactly 1, and `a x₀ - b x₋₁` scaled every position by that error each step, an error
/// that grew with the number of steps (1.4e-5 m after 7,680 steps on the dry patch, past
/// implicit Euler's).
#[inline(always)]
pub fn blend_rows(rows: &mut [StateRow], history: &mut [StateRow], blend: Bdf2Blend) {
    let b = blend.b;
    for (r, h) in rows.iter_mut().zip(history.iter_mut()) {
        let now = *r;
        if b != 0.0 {
            for l in 0..W {
                r.x.x[l] = now.x.x[l] + b * (now.x.x[l] - h.x.x[l]);
                r.x.y[l] = now.x.y[l] + b * (now.x.y[l] - h.x.y[l]);
                r.x.z[l] = now.x.z[l] + b * (now.x.z[l] - h.x.z[l]);
                r.v.x[l] = now.v.x[l] + b * (now.v.x[l] - h.v.x[l]);
                r.v.y[l] = now.v.y[l] + b * (now.v.y[l] - h.v.y[l]);
                r.v.z[l] = now.v.z[l] + b * (now.v.z[l] - h.v.z[l]);
            }
        }
        *h = now;
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
