//! The renderer without a window: a frame into an offscreen target read back to the host, and
//! a frame recorded but never submitted (the recording benchmark).

use super::Renderer;
use crate::error::Result;
use crate::render::frame::{FrameSync, FrameTimings};
use crate::render::graph::Outputs;
use crate::render::target::TargetView;
use crate::render::OffscreenTarget;
use crate::scene::Camera;

impl Renderer {
    /// Render one frame into `target` and copy it to the target's readback buffer; returns when
    /// the GPU is done, so `target.pixels()` holds the picture.
    pub fn render_offscreen(
        &mut self,
        target: &mut OffscreenTarget,
        camera: &Camera,
        time: f32,
    ) -> Result<FrameTimings> {
        let (slot, _) = self.begin_frame()?;
        let view = target.view();
        let outputs = Outputs { readback: Some(target.readback.raw), present: false };
        // The target's next frame starts from what this one leaves, if it ran.
        self.submit_frame(slot, &view, camera, time, FrameSync::default(), outputs)?;
        target.rendered(self.uses_target_depth());
        // Headless: wait right away, so the picture and the timings are ready.
        let timings = self.ring.wait(&self.device, slot)?.expect("the frame was submitted");
        Ok(self.with_counts(slot, timings))
    }

    /// The CPU side of one frame without its submission, for benchmarks (`benches/recording.rs`):
    /// take the next slot, write its uniforms and corner forces, and record the passes into
    /// `target` as `submit_frame` does. The command buffer is left executable and never
    /// submitted: the slot's fence stays signalled and its next `begin` resets the buffer.
    pub fn record_only(&mut self, target: &TargetView, camera: &Camera, time: f32) -> Result<()> {
        let (slot, _) = self.begin_frame()?;
        let uniforms = self.prepare_frame(slot, target, camera, time)?;
        // Never submitted: the resources stay as the last submitted frame left them.
        let entry = self.graph.states().clone();
        let frame = super::record::FrameIn { uniforms: &uniforms, time };
        let recorded = self.record_frame(slot, target, frame, Outputs::default()).map(|_| ());
        self.graph.set_states(entry);
        self.graph.frame_dropped();
        recorded
    }
}
