//! Fixed-step updates: [`Simulation::advance`] takes the host's frame time, adds it to an
//! accumulator, and takes as many steps of [`FixedStep::step`] as fit, carrying the rest to the
//! next frame. Hosts at 30, 60 or 144 Hz then compute the same steps, bit for bit, and only
//! the output (blended between the last two steps by the time left over) depends on when they
//! look.

use super::Simulation;
use crate::error::{invalid, Result};
use crate::params::FixedStep;
use crate::physics::head::head_between;

/// Time within this fraction of a step counts as the whole step. Frame times reach the
/// simulation rounded to f32 (1/144 s is not exact), so 144 frames of "1/144 s" may add up to
/// a hair under 120 steps of 1/120 s; without this a 144 Hz host would take 119 steps where a
/// 30 Hz host takes 120.
const SNAP: f64 = 1e-4;

/// What one [`Simulation::advance`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Advance {
    /// Steps taken (0 when the frame was shorter than what a step still needed).
    pub steps: u32,
    /// Where the output lies between the state before the last step (0) and after it (1):
    /// the time left over in the accumulator over the step. 1 when fixed steps are off or the
    /// output is not interpolated.
    pub blend: f32,
    /// Frame time dropped by the `max_frame` cap, s.
    pub dropped: f32,
}

/// The time the fixed steps still owe the host, s (f64: a long session's sum of f32 frame
/// times must not lose steps to rounding).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Accumulator {
    owed: f64,
}

/// The steps one frame takes: their count, the owed time before them (the head moves across
/// it), and the blend and dropped time after them.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Plan {
    steps: u32,
    span: f64,
    blend: f32,
    dropped: f32,
}

impl Accumulator {
    /// Adds `frame` seconds (capped at `f.max_frame`) and takes the whole steps that fit.
    fn take(&mut self, frame: f32, f: &FixedStep) -> Plan {
        let h = f.step as f64;
        let kept = frame.min(f.max_frame);
        self.owed += kept as f64;
        let span = self.owed;
        let mut steps = 0;
        while self.owed >= h * (1.0 - SNAP) {
            self.owed -= h;
            steps += 1;
        }
        self.owed = self.owed.max(0.0);
        Plan {
            steps,
            span,
            blend: (self.owed / h).min(1.0) as f32,
            dropped: frame - kept,
        }
    }
}

impl Simulation {
    /// Advances by a frame of `frame` seconds (finite, >= 0) in fixed steps of
    /// [`SimParams::fixed_step`](crate::SimParams::fixed_step): the frame's time is added to
    /// what is owed, and every whole step in it is taken; the rest waits for the next frame.
    /// Without fixed steps this is [`Simulation::step`] with `frame` (which must then be > 0).
    ///
    /// The head moves from where the last step left it to the transform last set, reached at
    /// the end of this frame: step k of n lands `k h / owed` of the way (rotation by slerp);
    /// the SDF colliders and skinned roots move the same way (a root's teleport is judged over
    /// the frame).
    /// With interpolation on, the vertices written after this call lie between the state
    /// before the last step and after it, by [`Advance::blend`]; [`Simulation::positions`]
    /// and the other state reads give the last step's state itself.
    pub fn advance(&mut self, frame: f32) -> Result<Advance> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        let f = self.params.fixed_step;
        if !f.on() {
            self.step(frame)?;
            return Ok(Advance {
                steps: 1,
                blend: 1.0,
                dropped: 0.0,
            });
        }
        if !(frame.is_finite() && frame >= 0.0) {
            return Err(invalid!("frame time must be finite and >= 0 s, got {frame}"));
        }
        let plan = self.fixed.take(frame, &f);
        let (from, to) = (self.head_prev, self.head);
        if plan.steps > 0 {
            // A jump is judged over the whole frame, not each of its (shorter) steps.
            self.teleport_roots()?;
            self.mark_frame_start();
        }
        for k in 1..=plan.steps {
            if k == plan.steps && f.interpolate {
                self.engine.keep_previous()?;
                self.show_blend(Some(plan.blend));
            }
            let a = (k as f64 * f.step as f64 / plan.span).min(1.0) as f32;
            self.step_to(f.step, head_between(&from, &to, a), Some(a))?;
        }
        if plan.steps == 0 && self.blend.is_some() {
            // No step: the same two states, blended further along (written at the next read).
            self.show_blend(Some(plan.blend));
            self.pose_follower_roots();
        }
        Ok(Advance {
            steps: plan.steps,
            blend: if f.interpolate { plan.blend } else { 1.0 },
            dropped: plan.dropped,
        })
    }

    /// Keeps where the SDFs, the colliders' own frames and skinned roots are as the start of this frame's fixed steps
    /// (copies into reused buffers: no allocation once they have grown).
    fn mark_frame_start(&mut self) {
        self.sdf_frames.mark_start();
        self.collider_frames.mark_start();
        self.mark_roots_start();
    }

    /// Forgets the owed time and the blend (a reset).
    pub(super) fn reset_fixed(&mut self) {
        self.fixed = Accumulator::default();
        if self.blend.is_some() {
            self.show_blend(None);
            self.pose_follower_roots();
        }
    }

    /// Shows the output `a` of the way from the state before the last step to after it
    /// (`None`: the last step's state).
    pub(super) fn show_blend(&mut self, a: Option<f32>) {
        self.engine.blend_output(a);
        self.blend = a;
    }

    /// Poses the followers' roots as the output shows them now (guides with skinned roots).
    fn pose_follower_roots(&mut self) {
        if let (Some(g), Some(r)) = (&mut self.guides, &mut self.roots) {
            g.pose_roots(r.shown(self.blend), self.engine.as_mut());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 30, 60 and 144 Hz hosts take 120 steps of 1/120 s in a second, with their frame times
    /// rounded to f32, and a 50 Hz host takes 2 or 3 a frame with the blend in between.
    #[test]
    fn the_accumulator_takes_the_same_steps_at_any_frame_rate() {
        let f = FixedStep::every(1.0 / 120.0);
        for hz in [30u32, 60, 144, 120, 240] {
            let mut acc = Accumulator::default();
            let steps: u32 = (0..hz).map(|_| acc.take(1.0 / hz as f32, &f).steps).sum();
            assert_eq!(steps, 120, "{hz} Hz");
            assert!(acc.owed < 1e-6, "{hz} Hz owes {}", acc.owed);
        }
        let mut acc = Accumulator::default();
        let p = acc.take(1.0 / 50.0, &f);
        assert_eq!(p.steps, 2);
        assert!((p.blend - 0.4).abs() < 1e-5, "{p:?}");
        let p = acc.take(1.0 / 50.0, &f);
        assert_eq!(p.steps, 2);
        assert!((p.blend - 0.8).abs() < 1e-5, "{p:?}");
        assert_eq!(acc.take(1.0 / 50.0, &f).steps, 3);
    }

    /// A frame past the cap takes the cap's steps and reports the rest dropped.
    #[test]
    fn a_hitch_is_capped() {
        let f = FixedStep {
            step: 0.01,
            max_frame: 0.1,
            interpolate: true,
        };
        let mut acc = Accumulator::default();
        let p = acc.take(2.0, &f);
        assert_eq!(p.steps, 10);
        assert!((p.dropped - 1.9).abs() < 1e-6, "{p:?}");
        assert_eq!(acc.take(0.0, &f).steps, 0);
    }
}
