//! The error budget ([`SimParams::tolerance`]): substeps chosen each frame from the live error
//! estimate (`estimate.rs`).
//!
//! After each step the estimate's largest point error `e` is compared with the tolerance `τ`:
//! above it and still rising, the substeps double (up to the cap); below `τ / 2^(p+1)` (p the integrator's
//! order), where half as many substeps would still keep the error under `τ / 2`, they halve
//! (down to the floor). The factor of two between the two thresholds keeps the choice from
//! flickering. The estimate is the error the positions carry, accumulated over the last
//! second or so, so it answers a change of substeps gradually: after each change the budget
//! waits [`SETTLE_FRAMES`] frames before the next, and an error over the tolerance that is
//! already falling (the finer substeps at work, damping taking out the old error) is left to
//! fall. Without that rule the budget ran the dry patch from 4 to 128 substeps under a 1e-4 m
//! tolerance, ending at half of it; with it, see `tests/estimate.rs`. The floor is the created substeps for the
//! explicit integrators (symplectic Euler and XPBD: fewer could be unstable, and the host chose
//! them stable) and 1 for the implicit ones (stable at any step). While the estimate is
//! withheld (water couples strands) the substeps stay.

use crate::params::{Integrator, SimParams};

/// Frames to wait after a change before the next (a third of a second at 30 Hz).
pub const SETTLE_FRAMES: u32 = 10;

/// The budget's state (see the module doc).
#[derive(Debug)]
pub(super) struct Budget {
    tolerance: f32,
    floor: u32,
    cap: u32,
    /// `2^p` for the integrator's order p.
    gain: f32,
    /// Frames left before the next change may happen.
    wait: u32,
    /// The error after the last step (infinite at the start: a first error is not rising).
    last: f32,
}

impl Budget {
    /// The budget of `p` for an engine running `integrator`; `None` without a tolerance.
    pub(super) fn new(p: &SimParams, integrator: Integrator) -> Option<Budget> {
        (p.tolerance > 0.0).then(|| Budget {
            tolerance: p.tolerance,
            floor: if integrator.is_implicit() { 1 } else { p.substeps },
            cap: p.max_substeps.max(p.substeps),
            gain: 2f32.powi(super::estimate::order(integrator)),
            wait: 0,
            last: f32::INFINITY,
        })
    }

    /// The substeps of the next step, after one at `n` that left the largest point error
    /// estimated at `err` (`None`: withheld).
    pub(super) fn next(&mut self, n: u32, err: Option<f32>) -> u32 {
        let Some(err) = err else { return n };
        let rising = err > self.last;
        self.last = err;
        if self.wait > 0 {
            self.wait -= 1;
            return n;
        }
        let m = if err > self.tolerance && rising {
            (2 * n).min(self.cap)
        } else if err * self.gain < 0.5 * self.tolerance {
            (n / 2).max(self.floor)
        } else {
            n
        };
        if m != n {
            self.wait = SETTLE_FRAMES;
        }
        m
    }

    /// Starts over (after a reset).
    pub(super) fn reset(&mut self) {
        self.wait = 0;
        self.last = f32::INFINITY;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn budget(integrator: Integrator) -> Budget {
        let p = SimParams {
            tolerance: 1e-4,
            substeps: 4,
            max_substeps: 32,
            ..SimParams::paper()
        };
        Budget::new(&p, integrator).unwrap()
    }

    #[test]
    fn doubles_over_the_tolerance_halves_well_under_it_and_waits_between() {
        let mut b = budget(Integrator::SYMPLECTIC_EULER);
        assert_eq!(b.next(4, Some(1.5e-4)), 4, "the first error is not rising");
        assert_eq!(b.next(4, Some(2e-4)), 8);
        for _ in 0..SETTLE_FRAMES {
            assert_eq!(b.next(8, Some(2e-4)), 8, "settling");
        }
        assert_eq!(b.next(8, Some(1.9e-4)), 8, "over but falling: left to fall");
        assert_eq!(b.next(8, Some(2e-4)), 16, "over and rising");
        b.reset();
        assert_eq!(b.next(16, Some(8e-5)), 16, "within the band: stays");
        assert_eq!(b.next(16, Some(2e-5)), 8, "2e-5 x 2 < 5e-5: halves");
        b.reset();
        b.next(32, Some(0.5));
        assert_eq!(b.next(32, Some(1.0)), 32, "capped");
        assert_eq!(
            b.next(4, Some(0.0)),
            4,
            "symplectic Euler's floor is the created substeps"
        );
        assert_eq!(b.next(4, None), 4, "withheld: stays");
    }

    #[test]
    fn implicit_integrators_may_go_down_to_one_substep() {
        let mut b = budget(Integrator::BDF2);
        assert_eq!(b.next(2, Some(1e-5)), 1, "BDF2: 1e-5 x 4 < 5e-5");
        let mut b = budget(Integrator::BDF2);
        assert_eq!(b.next(2, Some(2e-5)), 2, "2e-5 x 4 > 5e-5: halving would cost too much");
        assert!(budget(Integrator::IMPLICIT_EULER).next(1, Some(0.0)) == 1);
    }
}
