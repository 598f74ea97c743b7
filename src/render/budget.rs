//! A frame-time budget (`--budget-ms`): a closed loop that sets the LOD scale
//! (`Culling::lod_scale`) from the GPU time the frames measured, to hold the frame near the
//! budget. The LOD scale multiplies the full-density distance and divides the pixels per segment,
//! so the blades drawn grow about as its square: the controller steps the scale by the square
//! root of the time ratio, smoothed, and clamps each step.

/// Smallest and largest LOD scale the controller sets.
pub const SCALE_RANGE: (f32, f32) = (0.05, 4.0);
/// Fraction of the measured error corrected per frame (the rest waits for more frames: the
/// timings arrive a frame or more late with frames in flight).
const GAIN: f32 = 0.5;
/// Largest change of the scale in one step (×, and ÷).
const MAX_STEP: f32 = 1.5;

/// The controller's state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameBudget {
    /// The frame time to hold, in milliseconds.
    pub target_ms: f32,
    /// The LOD scale set last.
    pub scale: f32,
}

impl FrameBudget {
    /// Start at `scale` towards `target_ms`.
    pub fn new(target_ms: f32, scale: f32) -> Self {
        Self { target_ms, scale: scale.clamp(SCALE_RANGE.0, SCALE_RANGE.1) }
    }

    /// A frame rendered at the current scale took `gpu_ms`: the next scale.
    pub fn update(&mut self, gpu_ms: f64) -> f32 {
        if gpu_ms.is_finite() && gpu_ms > 0.0 {
            let ratio = (f64::from(self.target_ms) / gpu_ms) as f32;
            // Cost grows about as scale²: the scale that would meet the budget is scale·√ratio.
            let step = ratio.sqrt().powf(GAIN).clamp(1.0 / MAX_STEP, MAX_STEP);
            self.scale = (self.scale * step).clamp(SCALE_RANGE.0, SCALE_RANGE.1);
        }
        self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame costing `fixed + per_scale² · scale²` ms.
    fn settle(target: f32, fixed: f64, quadratic: f64, lag: usize) -> (f32, f64) {
        let mut budget = FrameBudget::new(target, 1.0);
        let mut pending = std::collections::VecDeque::from(vec![fixed + quadratic; lag]);
        let mut last = 0.0;
        for _ in 0..60 {
            let scale = f64::from(budget.scale);
            pending.push_back(fixed + quadratic * scale * scale);
            last = pending.pop_front().expect("queued");
            budget.update(last);
        }
        (budget.scale, last)
    }

    #[test]
    fn settles_near_the_budget_with_frames_in_flight() {
        for lag in [1, 2, 3] {
            // Unconstrained 100 ms; budgets of 50 and 75 ms.
            for target in [50.0, 75.0] {
                let (scale, ms) = settle(target, 20.0, 80.0, lag);
                assert!((ms - f64::from(target)).abs() < 0.05 * f64::from(target), "lag {lag}: {ms} ms for {target}");
                assert!(scale < 1.0);
            }
        }
    }

    #[test]
    fn a_generous_budget_raises_the_scale_and_bad_timings_change_nothing() {
        let (scale, _) = settle(400.0, 20.0, 80.0, 1);
        assert!(scale > 1.5, "{scale}");
        let mut budget = FrameBudget::new(50.0, 1.0);
        assert_eq!(budget.update(f64::NAN), 1.0);
        assert_eq!(budget.update(0.0), 1.0);
        // Unreachable budgets stop at the range.
        let (scale, _) = settle(1.0, 20.0, 80.0, 1);
        assert_eq!(scale, SCALE_RANGE.0);
    }
}
