//! What the renderer offers passes defined outside the library (a simulation, a bake, a test's
//! pass): adding them to every frame, temporal pairs, imports of their resources, the clock.

use super::Renderer;
use crate::render::graph::{Pass, Temporal, TemporalPair};
use crate::vk::{Access, Resource};

impl Renderer {
    /// Add `pass` to every frame, before the renderer's own passes (after those added before it):
    /// a simulation or a bake defined outside the library, with its own pipelines, sets and
    /// resources. Rebuilds keep it; the renderer destroys it with its own passes.
    pub fn add_pass(&mut self, pass: Box<dyn Pass>) {
        self.graph.add_extension(pass);
        self.ring.forget_replays();
    }

    /// Declare a temporal (ping-pong) pair over two resources of one shape (`graph::Temporal`):
    /// it swaps when a frame that wrote its current side is submitted.
    pub fn temporal(&mut self, pair: [Resource; 2]) -> Temporal {
        self.graph.temporal(pair)
    }

    /// `pair` as it stands before the next frame: which of its resources the next frame writes.
    pub fn temporal_pair(&self, pair: Temporal) -> TemporalPair {
        self.graph.temporal_pair(pair)
    }

    /// A resource made outside the renderer was last accessed by `accesses` (an upload, a clear):
    /// images must be imported before a pass uses them.
    pub fn import(&mut self, resource: Resource, accesses: &[Access]) {
        self.graph.import(resource, accesses);
    }

    /// Frames submitted so far: the next frame's `FrameClock::index`.
    pub fn frames_submitted(&self) -> u64 {
        self.graph.frames_submitted()
    }

    /// Set the simulation's fixed step (`FrameClock::dt`, seconds) of the next frames.
    pub fn set_time_step(&mut self, dt: f32) {
        self.time_step = dt;
    }
}
