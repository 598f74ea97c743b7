//! What a frame's passes know of time: the frame clock, and the temporal (ping-pong) pairs that
//! carry state from one submitted frame to the next.

use crate::vk::Resource;

/// A ping-pong pair declared once to the graph (`Graph::temporal`): two buffers or images of the
/// same shape that trade places. A pass reads `previous` (what the last submitted frame wrote)
/// and writes `current`; once a frame that wrote `current` is submitted, the pair swaps. A frame
/// that is dropped (failed to record or submit, or recorded only) does not swap it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Temporal(pub(super) usize);

/// A temporal pair as it stands: its two resources and which one is written this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TemporalPair {
    /// The two resources.
    pub pair: [Resource; 2],
    /// Index in `pair` of the resource written this frame.
    pub current: usize,
}

impl TemporalPair {
    /// The resource written this frame.
    pub fn current(&self) -> Resource {
        self.pair[self.current]
    }

    /// The resource the last submitted frame wrote.
    pub fn previous(&self) -> Resource {
        self.pair[1 - self.current]
    }
}

/// The frame's clock, as the passes see it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameClock {
    /// Frames submitted before this one: the frame's index once it is submitted (a dropped frame
    /// does not count, like a temporal pair's swap).
    pub index: u64,
    /// The simulation's fixed step in seconds (`Renderer::set_time_step`; 1/60 s by default).
    pub dt: f32,
    /// The simulation time of the frame in seconds.
    pub time: f64,
}

/// The simulation's step when none is set: 1/60 s.
pub const DEFAULT_DT: f32 = 1.0 / 60.0;
