//! The simulation's fixed time step (issue #29 item 4). Every frame advances the simulation by
//! whole steps of `dt` (`--dt`, default 1/60 s); a frame draws the last completed step, it does
//! not interpolate between the last two, so a frame at time T draws step ⌊T / dt⌋. Headless
//! commands (`render`, `bench`, `timing`) advance one step per frame, so their frames lie `dt`
//! apart whatever the machine's speed; `render` ends on the step at `--time`. The viewer
//! paces steps to real time (`StepPacer`): at most `MAX_STEPS_PER_FRAME` a frame, past which
//! simulated time falls behind real time and the panels say so. Today's models (static blades,
//! keyframes) are stateless: they are drawn at the step's time, and reaching a time takes no
//! warm-up. A stateful model reaches `--time T` by stepping from t = 0 (`StepClock::steps_to`).

/// The default step: 1/60 s.
pub const DEFAULT_DT: f64 = 1.0 / 60.0;
/// The longest step `--dt` takes: 1/15 s (a longer step would let a stateful model's explicit
/// integration skip whole oscillations of a stiff blade).
pub const MAX_DT: f64 = 1.0 / 15.0;
/// Steps the viewer runs in one frame at most; past that simulated time slows.
pub const MAX_STEPS_PER_FRAME: u32 = 4;

/// A fixed time step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepClock {
    /// Seconds per step, in (0, `MAX_DT`].
    pub dt: f64,
}

impl Default for StepClock {
    fn default() -> Self {
        Self { dt: DEFAULT_DT }
    }
}

impl StepClock {
    /// Steps from t = 0 to the last step at or before `time` (a time within 1e-9 of a step's counts
    /// as on it, so 1 s at 1/60 s is step 60): what a stateful model runs to reach `time`.
    pub fn steps_to(&self, time: f64) -> u64 {
        if time <= 0.0 {
            0
        } else {
            (time / self.dt + 1e-9).floor() as u64
        }
    }

    /// The time of step `step`.
    pub fn time_of(&self, step: u64) -> f64 {
        step as f64 * self.dt
    }

    /// The time a frame at `time` draws: its last completed step's (frames do not interpolate
    /// between the last two steps).
    pub fn drawn_at(&self, time: f64) -> f64 {
        self.time_of(self.steps_to(time))
    }

    /// The step `back` steps before the last one at or before `time` (not before step 0): the
    /// frames a headless command draws before its last.
    pub fn step_before(&self, time: f64, back: u32) -> u64 {
        self.steps_to(time).saturating_sub(u64::from(back))
    }
}

/// The viewer's steps: whole steps of the clock as real time passes, at most
/// `MAX_STEPS_PER_FRAME` a frame.
#[derive(Clone, Debug)]
pub struct StepPacer {
    clock: StepClock,
    /// Simulated time (seconds): a whole number of steps after the last jump.
    time: f64,
    /// Real time not yet stepped (under one step).
    carried: f64,
    /// The last frame wanted more steps than it ran.
    slowed: bool,
}

impl StepPacer {
    /// A pacer at simulated `time` (its last completed step).
    pub fn new(clock: StepClock, time: f64) -> Self {
        Self { clock, time: clock.drawn_at(time), carried: 0.0, slowed: false }
    }

    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The clock.
    pub fn clock(&self) -> StepClock {
        self.clock
    }

    /// Whether the last frame fell behind real time (it wanted more than `MAX_STEPS_PER_FRAME`).
    pub fn slowed(&self) -> bool {
        self.slowed
    }

    /// A frame after `elapsed` seconds of real time: the steps it runs. Past `MAX_STEPS_PER_FRAME`
    /// the rest is dropped (simulated time slows) and `slowed` says so.
    pub fn advance(&mut self, elapsed: f64) -> u32 {
        self.carried += elapsed.max(0.0);
        let due = (self.carried / self.clock.dt + 1e-9).floor();
        self.slowed = due > f64::from(MAX_STEPS_PER_FRAME);
        let steps = due.min(f64::from(MAX_STEPS_PER_FRAME)) as u32;
        self.carried = if self.slowed { 0.0 } else { (self.carried - f64::from(steps) * self.clock.dt).max(0.0) };
        self.time += f64::from(steps) * self.clock.dt;
        steps
    }

    /// Exactly one step (a script's fixed-step run): the same frames on every machine.
    pub fn step(&mut self) {
        self.slowed = false;
        self.time += self.clock.dt;
    }

    /// A jump to `time` (a script's time), to its last completed step: a stateful model restarts
    /// at equilibrium.
    pub fn jump(&mut self, time: f64) {
        self.time = self.clock.drawn_at(time);
        self.carried = 0.0;
        self.slowed = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_to_a_time_count_from_zero() {
        let clock = StepClock::default();
        assert_eq!(clock.steps_to(1.0), 60);
        assert_eq!(clock.steps_to(2.5), 150);
        assert_eq!(clock.steps_to(0.0), 0);
        assert_eq!(StepClock { dt: 0.05 }.steps_to(1.01), 20);
        assert_eq!(clock.step_before(1.0, 3), 57);
        assert_eq!(clock.step_before(0.01, 3), 0);
        // A frame draws the last completed step.
        assert_eq!(StepClock { dt: 0.05 }.drawn_at(0.03), 0.0);
        assert_eq!(clock.drawn_at(0.03), 1.0 / 60.0);
        assert_eq!(clock.drawn_at(2.5) as f32, 2.5);
    }

    #[test]
    fn the_viewer_runs_at_most_four_steps_a_frame_and_says_when_it_falls_behind() {
        let mut pacer = StepPacer::new(StepClock::default(), 0.0);
        // 60 frames of 1/60 s: one step each, in step with real time.
        let steps: u32 = (0..60).map(|_| pacer.advance(1.0 / 60.0)).sum();
        assert_eq!(steps, 60);
        assert!((pacer.time() - 1.0).abs() < 1e-9 && !pacer.slowed());
        // Half-step frames: a step every other frame.
        assert_eq!((0..10).map(|_| pacer.advance(1.0 / 120.0)).sum::<u32>(), 5);
        // A 0.2 s frame wants 12 steps: 4 run, simulated time slows.
        let before = pacer.time();
        assert_eq!(pacer.advance(0.2), MAX_STEPS_PER_FRAME);
        assert!(pacer.slowed());
        assert!((pacer.time() - before - 4.0 / 60.0).abs() < 1e-9);
        assert_eq!(pacer.advance(1.0 / 60.0), 1);
        assert!(!pacer.slowed());
        pacer.jump(5.0);
        assert_eq!(pacer.time() as f32, 5.0);
        pacer.step();
        assert!((pacer.time() - (5.0 + 1.0 / 60.0)).abs() < 1e-12);
    }
}
