//! Fixed-step updates ([`crate::Simulation::advance`]): the host hands over any frame time and
//! the simulation advances in steps of one fixed length, carrying the remainder to the next
//! frame, so what it computes does not depend on the host's frame rate.

use crate::error::{invalid, Result};

/// Most steps one [`crate::Simulation::advance`] may take (`max_frame / step`): a bound on the
/// work a single call can start.
pub const MAX_STEPS_PER_ADVANCE: u32 = 4096;

/// How [`crate::Simulation::advance`] divides frame time into steps (`sim/fixed.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedStep {
    /// The step, s, `0 < step <= 1`; 0 (the default) turns fixed steps off: `advance` then
    /// takes one step of the frame time as given.
    pub step: f32,
    /// Longest frame time one `advance` simulates, s (default 0.25): a longer frame (a hitch,
    /// a breakpoint) drops the excess rather than run many steps to catch up, which would make
    /// the next frame late too. Only such frames make the result depend on the frame rate.
    pub max_frame: f32,
    /// Whether the output shows the state between the last two steps, by the time left over
    /// (default on): motion then looks smooth at any frame rate, a step behind at most. It
    /// costs one copy of the positions per `advance` that steps; off, nothing is kept.
    pub interpolate: bool,
}

impl FixedStep {
    /// Off: `advance(dt)` is `step(dt)`.
    pub const OFF: FixedStep = FixedStep {
        step: 0.0,
        max_frame: 0.25,
        interpolate: true,
    };

    /// Fixed steps of `step` seconds, with the default cap and interpolation.
    pub fn every(step: f32) -> FixedStep {
        FixedStep { step, ..Self::OFF }
    }

    /// Whether fixed steps are on.
    pub fn on(&self) -> bool {
        self.step > 0.0
    }

    /// Checks the step and the cap (only when on).
    pub fn validate(&self) -> Result<()> {
        let FixedStep { step, max_frame, .. } = *self;
        if !(step.is_finite() && (0.0..=crate::sim::MAX_DT).contains(&step)) {
            return Err(invalid!("fixed_step must be 0 (off) or in (0, 1] s, got {step}"));
        }
        if !self.on() {
            return Ok(());
        }
        if !(max_frame.is_finite() && max_frame >= step) {
            return Err(invalid!(
                "max_frame_time must be finite and at least fixed_step ({step} s), got {max_frame}"
            ));
        }
        let steps = (max_frame as f64 / step as f64).ceil();
        if steps > MAX_STEPS_PER_ADVANCE as f64 {
            return Err(invalid!(
                "max_frame_time / fixed_step is {steps}: at most {MAX_STEPS_PER_ADVANCE} steps per advance"
            ));
        }
        Ok(())
    }
}
