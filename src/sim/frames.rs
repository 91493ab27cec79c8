//! Frames the host moves each step: the SDF colliders' and the analytic colliders' own
//! (bones). For each, where the host last set it, where the last step left it, and where the
//! frame of fixed steps began; a step moves each from where the last left it to where it was
//! set (or, inside a frame of fixed steps, part of the way there from the frame's start).

use crate::physics::head::head_between;
use glam::Affine3A;

/// One set of moving frames (empty where the scene has none: nothing is kept or moved).
#[derive(Clone, Debug, Default)]
pub(super) struct MovingFrames {
    /// As last set by the host.
    target: Vec<Affine3A>,
    /// Where the last step left them (the next step's start).
    last: Vec<Affine3A>,
    /// The next step's end (reused: no allocation once grown).
    next: Vec<Affine3A>,
    /// Where they were when the frame of fixed steps began (reused).
    start: Vec<Affine3A>,
}

impl MovingFrames {
    /// Frames at rest at `start`.
    pub(super) fn new(start: Vec<Affine3A>) -> Self {
        MovingFrames {
            target: start.clone(),
            last: start,
            next: Vec::new(),
            start: Vec::new(),
        }
    }

    /// How many frames.
    pub(super) fn len(&self) -> usize {
        self.target.len()
    }

    /// Whether there is none.
    pub(super) fn is_empty(&self) -> bool {
        self.target.is_empty()
    }

    /// Where the host last set them.
    pub(super) fn targets(&self) -> &[Affine3A] {
        &self.target
    }

    /// Sets where frame `i` is at the end of the next step (checked by the caller).
    pub(super) fn set(&mut self, i: usize, t: Affine3A) {
        self.target[i] = t;
    }

    /// Sets where every frame is at the end of the next step (as many as there are).
    pub(super) fn set_all(&mut self, to: &[Affine3A]) {
        self.target.copy_from_slice(to);
    }

    /// Hands the next step's start and end to `place` (the engine's, and the shadow's), then
    /// makes that end the next step's start, whatever `place` returns (its result is passed
    /// on). Nothing runs where there is no frame.
    pub(super) fn step_with(
        &mut self,
        frame: Option<f32>,
        place: impl FnOnce(&[Affine3A], &[Affine3A]) -> crate::error::Result<()>,
    ) -> crate::error::Result<()> {
        if self.is_empty() {
            return Ok(());
        }
        let (from, to) = self.next_step(frame);
        let r = place(from, to);
        self.stepped();
        r
    }

    /// The next step's start and end: the targets, or `a` of the way to them from where the
    /// frame of fixed steps began (`frame`). [`MovingFrames::stepped`] makes the end the next
    /// start.
    fn next_step(&mut self, frame: Option<f32>) -> (&[Affine3A], &[Affine3A]) {
        self.next.clear();
        match frame {
            None => self.next.extend_from_slice(&self.target),
            Some(a) => self
                .next
                .extend(self.start.iter().zip(&self.target).map(|(f, t)| head_between(f, t, a))),
        }
        (&self.last, &self.next)
    }

    /// The step that [`MovingFrames::next_step`] gave ran: its end is the next one's start.
    fn stepped(&mut self) {
        self.last.clone_from(&self.next);
    }

    /// Keeps where the frames are as the start of a frame of fixed steps.
    pub(super) fn mark_start(&mut self) {
        self.start.clone_from(&self.last);
    }

    /// After a reset: the frames are where they were last set, with no sweep from before.
    pub(super) fn reset(&mut self) {
        self.last.clone_from(&self.target);
    }
}
