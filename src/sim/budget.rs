//! The error budget ([`SimParams::tolerance`]): substeps, and AUTO's integrator (`auto.rs`),
//! chosen each frame from the live error estimate (`estimate.rs`).
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
//! them stable) and 1 for the implicit ones (stable at any step); under AUTO, symplectic
//! Euler's floor is its stability bound at the frame's dt. While the estimate is withheld
//! (water couples strands) the choice stays.

use super::auto::Auto;
use crate::params::{Integrator, SimParams};

/// Frames to wait after a change before the next (a third of a second at 30 Hz).
pub const SETTLE_FRAMES: u32 = 10;

/// The budget's state (see the module doc).
#[derive(Debug)]
pub(super) struct Budget {
    tolerance: f32,
    /// The created substeps (the explicit integrators' floor outside AUTO).
    created: u32,
    cap: u32,
    /// Frames left before the next change may happen.
    wait: u32,
    /// The error after the last step (infinite at the start: a first error is not rising).
    last: f32,
    /// AUTO's choice of integrator (only when the host asked for AUTO).
    auto: Option<Auto>,
}

/// What the budget chose for the next step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Choice {
    pub(super) integrator: Integrator,
    pub(super) substeps: u32,
}

impl Budget {
    /// The budget of `p` for an engine that resolved it to `integrator`; `explicit_h` is the
    /// groom's longest stable symplectic substep (read only under AUTO). `None` without a
    /// tolerance.
    pub(super) fn new(p: &SimParams, integrator: Integrator, explicit_h: impl FnOnce() -> f32) -> Option<Budget> {
        (p.tolerance > 0.0).then(|| Budget {
            tolerance: p.tolerance,
            created: p.substeps,
            cap: p.max_substeps.max(p.substeps),
            wait: 0,
            last: f32::INFINITY,
            auto: (p.integrator == Integrator::AUTO).then(|| Auto::new(integrator, explicit_h(), p.solver_iterations)),
        })
    }

    /// The fewest substeps `integrator` may run in a frame of `dt`.
    fn floor(&self, integrator: Integrator, dt: f32) -> u32 {
        match &self.auto {
            _ if integrator.is_implicit() => 1,
            Some(a) => a.floor(integrator, dt).min(self.cap),
            None => self.created,
        }
    }

    /// The substeps a step of `dt` must run at least: under AUTO, symplectic Euler's stability
    /// bound (a longer frame than the last needs more substeps before it is taken).
    pub(super) fn before(&self, integrator: Integrator, n: u32, dt: f32) -> u32 {
        if self.auto.is_some() {
            n.max(self.floor(integrator, dt))
        } else {
            n
        }
    }

    /// The next step's integrator and substeps, after a step of `dt` in which `integrator` ran
    /// `n` substeps and left the largest point error estimated at `err` (`None`: withheld).
    pub(super) fn next(&mut self, integrator: Integrator, n: u32, err: Option<f32>, dt: f32) -> Choice {
        let stay = Choice {
            integrator,
            substeps: n,
        };
        let Some(err) = err else { return stay };
        let rising = err > self.last;
        self.last = err;
        if self.wait > 0 {
            self.wait -= 1;
            return stay;
        }
        let gain = 2f32.powi(super::estimate::order(integrator));
        let m = if err > self.tolerance && rising {
            (2 * n).min(self.cap)
        } else if err * gain < 0.5 * self.tolerance {
            (n / 2).max(self.floor(integrator, dt))
        } else {
            n
        };
        let (tolerance, cap) = (self.tolerance, self.cap);
        let choice = match self
            .auto
            .as_mut()
            .and_then(|a| a.choose(integrator, n, err, m, dt, tolerance, cap))
        {
            Some((other, k)) => {
                // The old integrator's error is in the positions: none of it is rising now.
                self.last = f32::INFINITY;
                Choice {
                    integrator: other,
                    substeps: k,
                }
            }
            None => Choice {
                integrator,
                substeps: m,
            },
        };
        if choice != stay {
            self.wait = SETTLE_FRAMES;
        }
        choice
    }

    /// The backend cannot run `integrator` (AUTO asked for it): decide again next frame
    /// without it.
    pub(super) fn refuse(&mut self, integrator: Integrator) {
        if let Some(a) = &mut self.auto {
            a.refuse(integrator);
        }
        self.wait = 0;
    }

    /// The integrator to go back to on reset (AUTO's start), if AUTO chooses.
    pub(super) fn start(&self) -> Option<Integrator> {
        self.auto.as_ref().map(|a| a.start)
    }

    /// Starts over (after a reset).
    pub(super) fn reset(&mut self) {
        self.wait = 0;
        self.last = f32::INFINITY;
        if let Some(a) = &mut self.auto {
            a.reset();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 60.0;

    fn budget(integrator: Integrator) -> Budget {
        let p = SimParams {
            tolerance: 1e-4,
            substeps: 4,
            max_substeps: 32,
            integrator,
            ..SimParams::paper()
        };
        Budget::new(&p, integrator, || unreachable!("not AUTO")).unwrap()
    }

    fn n(b: &mut Budget, i: Integrator, n: u32, err: Option<f32>) -> u32 {
        let c = b.next(i, n, err, DT);
        assert_eq!(c.integrator, i, "not AUTO: the integrator stays");
        c.substeps
    }

    #[test]
    fn doubles_over_the_tolerance_halves_well_under_it_and_waits_between() {
        let se = Integrator::SYMPLECTIC_EULER;
        let mut b = budget(se);
        assert_eq!(n(&mut b, se, 4, Some(1.5e-4)), 4, "the first error is not rising");
        assert_eq!(n(&mut b, se, 4, Some(2e-4)), 8);
        for _ in 0..SETTLE_FRAMES {
            assert_eq!(n(&mut b, se, 8, Some(2e-4)), 8, "settling");
        }
        assert_eq!(n(&mut b, se, 8, Some(1.9e-4)), 8, "over but falling: left to fall");
        assert_eq!(n(&mut b, se, 8, Some(2e-4)), 16, "over and rising");
        b.reset();
        assert_eq!(n(&mut b, se, 16, Some(8e-5)), 16, "within the band: stays");
        assert_eq!(n(&mut b, se, 16, Some(2e-5)), 8, "2e-5 x 2 < 5e-5: halves");
        b.reset();
        n(&mut b, se, 32, Some(0.5));
        assert_eq!(n(&mut b, se, 32, Some(1.0)), 32, "capped");
        assert_eq!(
            n(&mut b, se, 4, Some(0.0)),
            4,
            "symplectic Euler's floor is the created substeps"
        );
        assert_eq!(n(&mut b, se, 4, None), 4, "withheld: stays");
        assert_eq!(b.before(se, 4, 1.0), 4, "outside AUTO nothing is raised before a step");
    }

    #[test]
    fn implicit_integrators_may_go_down_to_one_substep() {
        let bdf2 = Integrator::BDF2;
        let mut b = budget(bdf2);
        assert_eq!(n(&mut b, bdf2, 2, Some(1e-5)), 1, "BDF2: 1e-5 x 4 < 5e-5");
        let mut b = budget(bdf2);
        assert_eq!(
            n(&mut b, bdf2, 2, Some(2e-5)),
            2,
            "2e-5 x 4 > 5e-5: halving would cost too much"
        );
        let ie = Integrator::IMPLICIT_EULER;
        assert_eq!(n(&mut budget(ie), ie, 1, Some(0.0)), 1);
    }

    #[test]
    fn auto_raises_symplectic_euler_to_its_stability_bound_and_switches() {
        let se = Integrator::SYMPLECTIC_EULER;
        let p = SimParams {
            tolerance: 1e-4,
            substeps: 4,
            max_substeps: 512,
            integrator: Integrator::AUTO,
            ..SimParams::paper()
        };
        let mut b = Budget::new(&p, se, || 1.0 / 240.0).unwrap();
        assert_eq!(b.start(), Some(se));
        assert_eq!(b.before(se, 4, DT), 4);
        assert_eq!(b.before(se, 4, 1.0 / 30.0), 8, "a 30 Hz frame needs 8");
        assert_eq!(b.before(Integrator::BDF2, 1, 1.0 / 30.0), 1);
        assert_eq!(
            b.next(se, 8, Some(1e-4), DT),
            Choice {
                integrator: se,
                substeps: 8
            },
            "8 symplectic substeps cost less than one of BDF2 (NEWTON_COST)"
        );
        b.reset();
        let c = b.next(se, 256, Some(1e-4), DT);
        assert_eq!(
            c.integrator,
            Integrator::BDF2,
            "256 symplectic substeps cost more than BDF2 may"
        );
        let most = (256.0 / super::super::auto::NEWTON_COST) as u32;
        assert_eq!(c.substeps, most, "the most BDF2 substeps that cost no more than 256");
        for _ in 0..SETTLE_FRAMES {
            assert_eq!(b.next(Integrator::BDF2, most, Some(1e-5), DT), c, "settling");
        }
    }
}
