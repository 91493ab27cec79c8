//! Roots on a skinned mesh at the simulation's level ([`SimParams::skinned_roots`],
//! `physics/roots.rs`): the frames the host sets, where the last step left them, the teleport
//! test, and what a reset does with them. Both backends get the same calls. The frames are the
//! host's strands'; with guides the backend (and the estimate's shadow) gets its guides'
//! frames, and the followers' output every strand's as it shows them.

use super::Simulation;
use crate::error::{invalid, Error, Result};
use crate::groom::Groom;
use crate::physics::roots::{root_between, teleports, RootFrame};
use glam::{Affine3A, Vec3};

/// The root frames of every strand (host order).
#[derive(Debug)]
pub(super) struct RootTargets {
    /// With guides: each simulated strand's host strand, and each host strand's simulated
    /// strand (`NOT_SIMULATED` for a follower).
    guides: Option<(Vec<u32>, Vec<u32>)>,
    /// With guides: the simulated strands' frames before and after a step (reused).
    sim_from: Vec<RootFrame>,
    sim_to: Vec<RootFrame>,
    /// Where the step before the last left them: kept only where the followers show the fixed
    /// steps' blend between the last two steps.
    prev: Option<Vec<RootFrame>>,
    /// The frames the followers' output shows while that blend is on (reused).
    shown: Vec<RootFrame>,
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
    /// Every root at rest, for a simulation of `groom`, whose strands `host_of` (guide-groom
    /// order) are simulated as guides where it is given; `keep_prev` keeps the frames before
    /// the last step (followers that show the fixed steps' blend).
    pub(super) fn new(groom: &Groom, host_of: Option<&[u32]>, keep_prev: bool) -> RootTargets {
        let rest: Vec<Vec3> = (0..groom.strand_count())
            .map(|s| groom.positions()[groom.strand_range(s).start])
            .collect();
        let at_rest: Vec<RootFrame> = rest.iter().map(|r| RootFrame::at_rest(*r)).collect();
        let guides = host_of.map(|h| {
            let mut sim_of = vec![NOT_SIMULATED; rest.len()];
            for (g, &s) in h.iter().enumerate() {
                sim_of[s as usize] = g as u32;
            }
            (h.to_vec(), sim_of)
        });
        RootTargets {
            guides,
            sim_from: Vec::new(),
            sim_to: Vec::new(),
            prev: keep_prev.then(|| at_rest.clone()),
            shown: Vec::new(),
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

    /// Every `stride`-th simulated strand's targets (the error estimate's shadow runs those
    /// strands), read in place: only the sampled strands' frames are copied.
    pub(super) fn targets_every(&self, stride: usize) -> impl Iterator<Item = RootFrame> + '_ {
        let simulated = self
            .guides
            .as_ref()
            .map_or(self.target.len(), |(host_of, _)| host_of.len());
        (0..simulated).step_by(stride.max(1)).map(move |s| match &self.guides {
            Some((host_of, _)) => self.target[host_of[s] as usize],
            None => self.target[s],
        })
    }

    /// The frames the followers' output shows: where the last step left them, or `a` of the
    /// way there from the step before while the fixed steps' output blends.
    pub(super) fn shown(&mut self, blend: Option<f32>) -> &[RootFrame] {
        match (blend, &self.prev) {
            (Some(a), Some(prev)) if a < 1.0 => {
                self.shown.clear();
                let between = prev.iter().zip(&self.last).map(|(p, l)| root_between(p, l, a));
                self.shown.extend(between);
                &self.shown
            }
            _ => &self.last,
        }
    }

    /// `frames` (host order) as the backend's strands take them: the guides' with guides,
    /// gathered into `out`.
    fn simulated<'a>(
        guides: &Option<(Vec<u32>, Vec<u32>)>,
        frames: &'a [RootFrame],
        out: &'a mut Vec<RootFrame>,
    ) -> &'a [RootFrame] {
        match guides {
            Some((host_of, _)) => {
                out.clear();
                out.extend(host_of.iter().map(|&h| frames[h as usize]));
                out
            }
            None => frames,
        }
    }
}

/// A host strand no guide simulates.
const NOT_SIMULATED: u32 = u32::MAX;

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
    /// they start the step on their targets, at rest. With guides the backend carries the
    /// guides among them; a follower's output follows its frame wherever it goes.
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
                let sim = match &r.guides {
                    Some((_, sim_of)) => sim_of[s],
                    None => s as u32,
                };
                if sim != NOT_SIMULATED {
                    r.carried.push(sim);
                    r.carry_from.push(*last);
                    r.carry_to.push(*target);
                }
                *last = *target;
                if let Some(prev) = &mut r.prev {
                    prev[s] = *target;
                }
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
        let from = RootTargets::simulated(&r.guides, &r.last, &mut r.sim_from);
        let to = RootTargets::simulated(&r.guides, &next, &mut r.sim_to);
        let res = self.engine.place_roots(from, to);
        if let Some(sh) = &mut self.shadow {
            sh.place_roots(to);
        }
        if let Some(prev) = &mut r.prev {
            std::mem::swap(prev, &mut r.last);
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

    /// After the engine's reset to the rest pose under `head`: carries every simulated strand
    /// onto its target frame (from where the head put its root), so the reset pose hangs from
    /// the roots.
    pub(super) fn reset_roots(&mut self, head: &Affine3A) -> Result<()> {
        let Some(r) = &mut self.roots else {
            return Ok(());
        };
        let (_, rot, _) = head.to_scale_rotation_translation();
        let from_head = |s: usize| RootFrame {
            position: head.transform_point3(r.rest[s]),
            rotation: rot,
        };
        r.carried.clear();
        r.carry_from.clear();
        r.carry_to.clear();
        match &r.guides {
            Some((host_of, _)) => {
                r.carried.extend(0..host_of.len() as u32);
                r.carry_from.extend(host_of.iter().map(|&h| from_head(h as usize)));
                r.carry_to.extend(host_of.iter().map(|&h| r.target[h as usize]));
            }
            None => {
                r.carried.extend(0..r.target.len() as u32);
                r.carry_from.extend((0..r.target.len()).map(from_head));
                r.carry_to.extend_from_slice(&r.target);
            }
        }
        r.last.clone_from(&r.target);
        if let Some(prev) = &mut r.prev {
            prev.clone_from(&r.target);
        }
        self.engine.carry_strands(&r.carried, &r.carry_from, &r.carry_to)
    }
}
