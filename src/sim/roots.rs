//! Roots on a skinned mesh at the simulation's level ([`SimParams::skinned_roots`],
//! `physics/roots.rs`): the frames the host sets, where the last step left them, the teleport
//! test, and what a reset does with them. Both backends get the same calls.

use super::Simulation;
use crate::error::{invalid, Error, Result};
use crate::groom::Groom;
use crate::physics::roots::{root_between, teleports, RootFrame};
use glam::{Affine3A, Vec3};

/// The root frames of every strand (host order).
#[derive(Debug)]
pub(super) struct RootTargets {
    /// Each strand's first point at rest (head space).
    rest: Vec<Vec3>,
    /// As last set by the host (reached at the end of the next step or frame).
    pub(super) target: Vec<RootFrame>,
    /// Where the last step left them.
    last: Vec<RootFrame>,
    /// The next step's (reused).
    next: Vec<RootFrame>,
    /// Where they were when the frame of fixed steps began (reused).
    start: Vec<RootFrame>,
    /// Strands to carry, and their frames before and after (reused).
    carried: Vec<u32>,
    carry_from: Vec<RootFrame>,
    carry_to: Vec<RootFrame>,
}

impl RootTargets {
    /// Every root at rest, for a simulation of `groom`.
    pub(super) fn new(groom: &Groom) -> RootTargets {
        let rest: Vec<Vec3> = (0..groom.strand_count())
            .map(|s| groom.positions()[groom.strand_range(s).start])
            .collect();
        let at_rest: Vec<RootFrame> = rest.iter().map(|r| RootFrame::at_rest(*r)).collect();
        RootTargets {
            rest,
            target: at_rest.clone(),
            last: at_rest,
            next: Vec::new(),
            start: Vec::new(),
            carried: Vec::new(),
            carry_from: Vec::new(),
            carry_to: Vec::new(),
        }
    }

    /// Every `stride`-th strand's targets (the error estimate's shadow runs those strands).
    pub(super) fn targets_every(&self, stride: usize) -> impl Iterator<Item = RootFrame> + '_ {
        self.target.iter().step_by(stride.max(1)).copied()
    }
}

impl Simulation {
    /// Sets where every strand's root is at the end of the next step (or, for
    /// [`Simulation::advance`], the next frame): one frame per strand, in the groom's order: the
    /// strand's first point in the world and the rotation from the groom's rest frame. Needs
    /// [`crate::SimParams::skinned_roots`]. All or nothing: a bad frame changes none.
    pub fn set_root_frames(&mut self, frames: &[RootFrame]) -> Result<()> {
        self.set_roots_by(frames.len(), |s| frames[s])
    }

    /// [`Simulation::set_root_frames`] with frame `s` of `n` given by `frame(s)` (read twice:
    /// checked, then kept), so that the C ABI copies the host's arrays without allocating.
    pub(crate) fn set_roots_by(&mut self, n: usize, frame: impl Fn(usize) -> RootFrame) -> Result<()> {
        self.check_device()?;
        let Some(r) = &mut self.roots else {
            return Err(Error::Unsupported(
                "root frames need SimParams::skinned_roots (desc.skinned_roots) on at create".into(),
            ));
        };
        if n != r.target.len() {
            return Err(invalid!(
                "{n} root frames for {} strands: give one per strand",
                r.target.len()
            ));
        }
        for s in 0..n {
            let f = frame(s);
            if !f.position.is_finite() {
                return Err(invalid!("root frame {s}: position {} is not finite", f.position));
            }
            let len = f.rotation.length();
            if !(len.is_finite() && (len - 1.0).abs() <= 1e-3) {
                return Err(invalid!(
                    "root frame {s}: rotation {:?} must be a unit quaternion (length {len})",
                    f.rotation
                ));
            }
        }
        for (s, t) in r.target.iter_mut().enumerate() {
            let f = frame(s);
            *t = RootFrame {
                position: f.position,
                rotation: f.rotation.normalize(),
            };
        }
        Ok(())
    }

    /// Carries the strands whose roots jump farther than the teleport distance between where
    /// the last step left them and their targets (before a step, or a frame of fixed steps):
    /// they start the step on their targets, at rest.
    pub(super) fn teleport_roots(&mut self) -> Result<()> {
        let Some(r) = &mut self.roots else {
            return Ok(());
        };
        let d = self.params.root_teleport_distance;
        r.carried.clear();
        r.carry_from.clear();
        r.carry_to.clear();
        for (s, (last, target)) in r.last.iter_mut().zip(&r.target).enumerate() {
            if teleports(last, target, d) {
                r.carried.push(s as u32);
                r.carry_from.push(*last);
                r.carry_to.push(*target);
                *last = *target;
            }
        }
        if r.carried.is_empty() {
            return Ok(());
        }
        self.engine.carry_strands(&r.carried, &r.carry_from, &r.carry_to)
    }

    /// Moves the roots over the next step to their targets, or `a` of the way there from where
    /// the frame began (`frame`: fixed steps inside a frame); the shadow follows.
    pub(super) fn place_roots(&mut self, frame: Option<f32>) -> Result<()> {
        let Some(r) = &mut self.roots else {
            return Ok(());
        };
        let mut next = std::mem::take(&mut r.next);
        next.clear();
        match frame {
            None => next.extend_from_slice(&r.target),
            Some(a) => next.extend(r.start.iter().zip(&r.target).map(|(f, t)| root_between(f, t, a))),
        }
        let res = self.engine.place_roots(&r.last, &next);
        if let Some(sh) = &mut self.shadow {
            sh.place_roots(&next);
        }
        r.last.clone_from(&next);
        r.next = next;
        res
    }

    /// Keeps where the roots are as the start of this frame's fixed steps.
    pub(super) fn mark_roots_start(&mut self) {
        if let Some(r) = &mut self.roots {
            r.start.clone_from(&r.last);
        }
    }

    /// After the engine's reset to the rest pose under `head`: carries every strand onto its
    /// target frame (from where the head put its root), so the reset pose hangs from the roots.
    pub(super) fn reset_roots(&mut self, head: &Affine3A) -> Result<()> {
        let Some(r) = &mut self.roots else {
            return Ok(());
        };
        let (_, rot, _) = head.to_scale_rotation_translation();
        r.carried.clear();
        r.carried.extend(0..r.target.len() as u32);
        r.carry_from.clear();
        r.carry_from.extend(r.rest.iter().map(|p| RootFrame {
            position: head.transform_point3(*p),
            rotation: rot,
        }));
        r.last.clone_from(&r.target);
        self.engine.carry_strands(&r.carried, &r.carry_from, &r.target)
    }
}
