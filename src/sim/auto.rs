//! AUTO under an error budget: each settled frame, symplectic Euler or BDF2, whichever the
//! errors seen so far say keeps the estimate under the tolerance at the least cost.
//!
//! Cost is counted in symplectic substeps: a BDF2 substep costs [`NEWTON_COST`] of them per
//! Newton iteration (deterministic, so that the choice, and with it the results, is the same
//! on every run; measured wall time would not be). Each integrator's error is modelled from
//! the last settled frame it ran: `e (h' / h)^p` at substep `h'` if it left the largest point
//! error `e` at substep `h` (p its order). An integrator that has not run yet is tried once
//! its cheapest setting (symplectic Euler at its stability bound, BDF2 at one substep) costs
//! at most half of what the current one needs, at the most substeps that cost no more than
//! now; afterwards its own errors decide. A switch needs the other to be [`HYSTERESIS`] times
//! cheaper, so that two close costs do not flicker. Symplectic Euler never runs above its
//! stability bound ([`crate::plan::integrator::explicit_max_substep`]) at the frame's dt.

use crate::params::Integrator;

/// Cost of one Newton iteration of a BDF2 substep, in symplectic Euler substeps. From the
/// accuracy report (`docs/report/work_precision.csv`, 2026-11-26, the dry patch: 2.37 ms per
/// simulated second for BDF2 with 1 Newton iteration at 1 substep, 0.59 ms for symplectic
/// Euler at 4, so 16; the stiff patch 13.5) and the frame bench's integrator table (implicit
/// Euler with one iteration 16-17x a symplectic step). It was 40 before the solve was
/// vectorised.
pub const NEWTON_COST: f32 = 16.0;

/// How much cheaper the other integrator must be predicted to be before AUTO switches.
pub const HYSTERESIS: f32 = 1.5;

/// The candidates, in index order.
const CANDIDATES: [Integrator; 2] = [Integrator::SYMPLECTIC_EULER, Integrator::BDF2];

/// AUTO's state (see the module doc).
#[derive(Debug)]
pub(super) struct Auto {
    /// The integrator AUTO resolved to at create (and returns to on reset).
    pub(super) start: Integrator,
    /// Symplectic Euler's longest stable substep, s.
    explicit_h: f32,
    /// One BDF2 substep, in symplectic substeps.
    bdf2_cost: f32,
    /// Per candidate: the largest point error and the substep of its last settled frame.
    seen: [Option<(f32, f32)>; 2],
    /// Per candidate: whether the backend refused it.
    refused: [bool; 2],
}

fn index(i: Integrator) -> usize {
    usize::from(i == Integrator::BDF2)
}

impl Auto {
    /// AUTO starting at `start` (symplectic Euler or BDF2) on a groom whose symplectic Euler is
    /// stable up to substeps of `explicit_h`, with `newton` iterations per implicit substep.
    pub(super) fn new(start: Integrator, explicit_h: f32, newton: u32) -> Auto {
        Auto {
            start,
            explicit_h,
            bdf2_cost: NEWTON_COST * newton as f32,
            seen: [None; 2],
            refused: [false; 2],
        }
    }

    /// The fewest substeps `integrator` may run in a frame of `dt`.
    pub(super) fn floor(&self, integrator: Integrator, dt: f32) -> u32 {
        if integrator.is_implicit() {
            1
        } else {
            // f64: dt / h can sit a rounding away from an integer.
            ((dt as f64 / self.explicit_h as f64).ceil() as u32).max(1)
        }
    }

    fn cost(&self, integrator: Integrator, n: u32) -> f32 {
        n as f32 * if integrator.is_implicit() { self.bdf2_cost } else { 1.0 }
    }

    /// After a settled frame of `dt` in which `cur` ran `n` substeps and left the largest
    /// point error `err`, and the substep rule chose `m` next (`cap` the most it may): the
    /// other candidate and its substeps, if switching to it is the cheaper way to keep the
    /// error under `tolerance`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn choose(
        &mut self,
        cur: Integrator,
        n: u32,
        err: f32,
        m: u32,
        dt: f32,
        tolerance: f32,
        cap: u32,
    ) -> Option<(Integrator, u32)> {
        self.seen[index(cur)] = Some((err, dt / n as f32));
        let other = CANDIDATES[1 - index(cur)];
        let floor = self.floor(other, dt);
        if self.refused[index(other)] || floor > cap {
            return None;
        }
        let now = self.cost(cur, m);
        let stuck = m == cap && err > tolerance;
        let want = match self.seen[index(other)] {
            Some((e, h)) => {
                let p = super::estimate::order(other) as f32;
                let h_ok = h * (0.5 * tolerance / e.max(f32::MIN_POSITIVE)).powf(1.0 / p);
                let n_ok = ((dt / h_ok).ceil() as u32).max(floor);
                (n_ok <= cap && self.cost(other, n_ok) * HYSTERESIS <= now).then_some(n_ok)
            }
            None => (2.0 * self.cost(other, floor) <= now || stuck)
                .then(|| ((now / self.cost(other, 1)) as u32).clamp(floor, cap)),
        };
        want.map(|k| (other, k))
    }

    /// The backend cannot run `integrator`: never choose it again.
    pub(super) fn refuse(&mut self, integrator: Integrator) {
        self.refused[index(integrator)] = true;
    }

    /// Forgets what was seen (after a reset).
    pub(super) fn reset(&mut self) {
        self.seen = [None; 2];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SE: Integrator = Integrator::SYMPLECTIC_EULER;
    const BDF2: Integrator = Integrator::BDF2;

    #[test]
    fn tries_bdf2_once_symplectic_euler_needs_far_more_substeps() {
        // Stable up to 1/480 s: 8 substeps of a 60 Hz frame.
        let mut a = Auto::new(SE, 1.0 / 480.0, 1);
        let dt = 1.0 / 60.0;
        assert_eq!(a.floor(SE, dt), 8);
        assert_eq!(a.choose(SE, 8, 2e-4, 16, dt, 1e-4, 512), None, "16 < 2 x NEWTON_COST");
        let most = (128.0 / NEWTON_COST) as u32;
        assert_eq!(
            a.choose(SE, 64, 2e-4, 128, dt, 1e-4, 512),
            Some((BDF2, most)),
            "tried at the most substeps costing no more than 128 symplectic ones"
        );
        // Symplectic Euler left 2e-4 m at 64 substeps: it would need 256 for 5e-5 m, more
        // than BDF2's substeps cost (at most 128).
        assert_eq!(a.choose(BDF2, most, 1e-6, most, dt, 1e-4, 512), None, "BDF2 stays");
        let mut a = Auto::new(SE, 1.0 / 480.0, 1);
        a.choose(SE, 8, 1e-5, 8, dt, 1e-4, 512);
        // Symplectic Euler at 8 substeps left 1e-5 m: cost 8 against BDF2's NEWTON_COST and
        // more.
        assert_eq!(
            a.choose(BDF2, 1, 1e-6, 1, dt, 1e-4, 512),
            Some((SE, 8)),
            "back to symplectic Euler at its stability bound"
        );
    }

    #[test]
    fn stays_where_the_other_is_unknown_and_not_much_cheaper_or_refused() {
        let mut a = Auto::new(BDF2, 1.0 / 7680.0, 2);
        let dt = 1.0 / 60.0;
        assert_eq!(a.floor(SE, dt), 128);
        assert_eq!(
            a.choose(BDF2, 1, 1e-6, 1, dt, 1e-4, 512),
            None,
            "128 symplectic > 2 NEWTON_COST"
        );
        let mut a = Auto::new(SE, 1.0 / 480.0, 1);
        a.refuse(BDF2);
        assert_eq!(a.choose(SE, 256, 2e-4, 512, dt, 1e-4, 512), None, "refused");
        let mut a = Auto::new(SE, 1.0 / 480.0, 1);
        assert_eq!(
            a.choose(SE, 512, 2e-4, 512, dt, 1e-4, 512),
            Some((BDF2, (512.0 / NEWTON_COST) as u32)),
            "stuck at the cap over the tolerance"
        );
    }
}
