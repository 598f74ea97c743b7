//! The one measuring loop of `meadow bench` (every preset), `meadow overhead` and `meadow timing`:
//! warm-up rounds then measured rounds, each round one frame of every variant in turn (A B C
//! A B C …, so their ratios survive a noisy machine), every frame counted towards the progress
//! report (and a signal checked), the frames still in flight drained at the end, and each
//! frame's [`FrameTimings`] kept with its round. What differs between the commands is the
//! [`Subject`]: how a variant renders a frame (offscreen and waited for, or pipelined with frames
//! in flight), its camera and simulation time, and what it keeps of the picture.

use crate::error::Result;
use crate::render::{FrameTimings, OffscreenTarget, Renderer};
use crate::scene::Camera;

use super::Progress;

/// How many rounds the loop renders: `warmup` discarded, then `frames` measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Schedule {
    /// Rounds discarded first.
    pub warmup: u32,
    /// Rounds measured.
    pub frames: u32,
}

impl Schedule {
    /// Every round, warm-up included.
    pub fn rounds(self) -> u32 {
        self.warmup + self.frames
    }
}

/// One finished frame of a variant: its round (from 0, warm-up included) and its timings.
pub(crate) struct Frame {
    pub(crate) index: u32,
    pub(crate) timings: FrameTimings,
}

/// What the loop measures: `variants()` renderers, one frame each per round.
pub(crate) trait Subject {
    /// How many variants render in turn each round.
    fn variants(&self) -> usize;

    /// Render (or submit) frame `round` of variant `i`; returns the frame that finished meanwhile,
    /// if any (this one, when rendering waits for it; an earlier one with frames in flight).
    fn frame(&mut self, i: usize, round: u32) -> Result<Option<Frame>>;

    /// The frames of variant `i` still in flight after the last round.
    fn drain(&mut self, _i: usize) -> Result<Vec<Frame>> {
        Ok(Vec::new())
    }
}

/// What the loop measured: per variant, every finished frame in round order.
pub(crate) struct Measured {
    schedule: Schedule,
    frames: Vec<Vec<Frame>>,
}

impl Measured {
    /// Variant `i`'s frames, warm-up included, in round order.
    pub fn all(&self, i: usize) -> &[Frame] {
        &self.frames[i]
    }

    /// Variant `i`'s measured frames (the warm-up discarded), in round order.
    pub fn timings(&self, i: usize) -> impl Iterator<Item = &FrameTimings> {
        self.frames[i].iter().filter(|f| f.index >= self.schedule.warmup).map(|f| &f.timings)
    }

    /// Every variant's frames, warm-up included.
    pub fn into_frames(self) -> Vec<Vec<Frame>> {
        self.frames
    }
}

/// The measuring loop: `schedule`'s rounds of one frame of every variant of `subject` in turn,
/// each counted by `progress` (which stops the loop on a signal), then what is in flight drained.
pub(crate) fn measure(subject: &mut dyn Subject, schedule: Schedule, progress: &mut Progress) -> Result<Measured> {
    let n = subject.variants();
    let mut frames: Vec<Vec<Frame>> = (0..n).map(|_| Vec::new()).collect();
    for round in 0..schedule.rounds() {
        for (i, done) in frames.iter_mut().enumerate() {
            done.extend(subject.frame(i, round)?);
            progress.rendered()?;
        }
    }
    for (i, done) in frames.iter_mut().enumerate() {
        done.extend(subject.drain(i)?);
        done.sort_by_key(|f| f.index);
    }
    Ok(Measured { schedule, frames })
}

/// What sees each frame's picture: the variant, its renderer, and the target it rendered into.
pub(crate) type AfterFrame<'a> = &'a mut dyn FnMut(usize, &Renderer, &OffscreenTarget);

/// The common subject: renderers that each render a frame offscreen and wait for it, into one
/// target they share or one target each, from `camera(i, round)` at simulation time
/// `time(round)`; `after(i, target)` sees each frame's picture.
pub(crate) struct Offscreen<'a> {
    /// The renderers, one per variant.
    pub renderers: &'a mut [Renderer],
    /// One target for all (read after each frame only) or one per renderer.
    pub targets: &'a mut [OffscreenTarget],
    /// Variant `i`'s camera in round `round`.
    pub camera: &'a dyn Fn(usize, u32) -> Camera,
    /// The simulation time of round `round`, in seconds.
    pub time: &'a dyn Fn(u32) -> f32,
    /// Called with each rendered frame's variant and target.
    pub after: Option<AfterFrame<'a>>,
}

impl Subject for Offscreen<'_> {
    fn variants(&self) -> usize {
        self.renderers.len()
    }

    fn frame(&mut self, i: usize, round: u32) -> Result<Option<Frame>> {
        let target = match self.targets.len() {
            1 => &mut self.targets[0],
            _ => &mut self.targets[i],
        };
        let timings = self.renderers[i].render_offscreen(target, &(self.camera)(i, round), (self.time)(round))?;
        if let Some(after) = self.after.as_mut() {
            after(i, &self.renderers[i], target);
        }
        Ok(Some(Frame { index: round, timings }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two variants, each with `lag` frames in flight: a frame comes back `lag` rounds after it
    /// was submitted, the rest when drained. Records the order of the calls.
    struct Queued {
        lag: u32,
        submitted: Vec<Vec<u32>>,
        calls: Vec<(usize, u32)>,
    }

    impl Subject for Queued {
        fn variants(&self) -> usize {
            self.submitted.len()
        }

        fn frame(&mut self, i: usize, round: u32) -> Result<Option<Frame>> {
            self.calls.push((i, round));
            self.submitted[i].push(round);
            let back = round.checked_sub(self.lag);
            // A frame's GPU time tells which it was: 10 × variant + round.
            Ok(back.map(|index| Frame { index, timings: timings(i, index) }))
        }

        fn drain(&mut self, i: usize) -> Result<Vec<Frame>> {
            let rounds = self.submitted[i].len() as u32;
            // Returned out of order: the loop sorts.
            Ok((rounds.saturating_sub(self.lag)..rounds)
                .rev()
                .map(|index| Frame { index, timings: timings(i, index) })
                .collect())
        }
    }

    fn timings(i: usize, index: u32) -> FrameTimings {
        FrameTimings { gpu_ms: 10.0 * i as f64 + f64::from(index), ..Default::default() }
    }

    #[test]
    fn the_loop_interleaves_discards_the_warmup_and_drains_what_is_in_flight() {
        for lag in [0, 2] {
            let mut subject = Queued { lag, submitted: vec![Vec::new(); 2], calls: Vec::new() };
            let mut reported = Vec::new();
            let mut report = |done, total| reported.push((done, total));
            let mut progress = Progress::new(10, &mut report);
            let measured = measure(&mut subject, Schedule { warmup: 2, frames: 3 }, &mut progress).expect("measured");
            // A B A B …: one frame of each variant per round.
            let order: Vec<(usize, u32)> = (0..5).flat_map(|r| [(0, r), (1, r)]).collect();
            assert_eq!(subject.calls, order, "lag {lag}");
            assert_eq!(reported, (1..=10).map(|d| (d, 10)).collect::<Vec<_>>(), "every frame counted");
            for i in 0..2 {
                let all: Vec<u32> = measured.all(i).iter().map(|f| f.index).collect();
                assert_eq!(all, [0, 1, 2, 3, 4], "lag {lag}, variant {i}: every round, in order");
                let kept: Vec<f64> = measured.timings(i).map(|t| t.gpu_ms).collect();
                let expected: Vec<f64> = (2..5).map(|r| 10.0 * i as f64 + f64::from(r)).collect();
                assert_eq!(kept, expected, "lag {lag}, variant {i}: the measured rounds only");
            }
        }
    }
}
