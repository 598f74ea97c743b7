//! Recording a frame: its plan, a kept recording replayed when it still holds, or the passes
//! recorded with their queries sized to the plan.

use std::time::Instant;

use super::Renderer;
use crate::error::Result;
use crate::render::frame::{FrameUniforms, Replay, ReplayKey};
use crate::render::graph::{FrameClock, Outputs, PassContext};
use crate::render::submission::Strategy;
use crate::render::target::TargetView;
use crate::vk::{Access, Resource};

/// What a frame is recorded from besides its target: its uniforms and simulation time.
#[derive(Clone, Copy)]
pub(super) struct FrameIn<'a> {
    pub(super) uniforms: &'a FrameUniforms,
    pub(super) time: f32,
}

impl Renderer {
    /// Record the frame of `slot` into `target` (after `begin_frame`), or replay a pre-recorded
    /// one whose barriers assumed the same target and resource states and whose passes' commands
    /// are this frame's (`graph::Plan::replay`). Returns when recording began.
    pub(super) fn record_frame(
        &mut self,
        slot: usize,
        target: &TargetView,
        frame_in: FrameIn,
        outputs: Outputs,
    ) -> Result<Instant> {
        let started = Instant::now();
        self.graph.import(Resource::color(target.color), &[target.color_previous]);
        self.graph.import(Resource::depth(target.depth), &[target.depth_previous]);
        let scene_view = self.scene_view(target)?;
        let device = &*self.device;
        let prerecorded = self.settings.submission.strategy == Strategy::Prerecorded;
        let frame = self.ring.frame_mut(slot);
        let key = ReplayKey::new(target, outputs);
        let clock = FrameClock { index: 0, dt: self.time_step, time: f64::from(frame_in.time) };
        let ctx = PassContext {
            device,
            target: &scene_view,
            output: target,
            slot,
            descriptor_set: self.scene_frames[slot].set,
            uniforms: frame_in.uniforms,
            clock,
            step: 0,
            temporals: &[],
        };
        let plan = self.graph.plan(&ctx, prerecorded)?;
        frame.replayed = false;
        if let (true, Some(replay), Some(passes)) = (prerecorded, frame.replay.as_ref(), plan.replay()) {
            if replay.target == key && replay.passes == passes && &replay.entry == self.graph.states() {
                // Uniforms and forces live in buffers written before: the same commands render
                // this frame.
                self.graph.set_states(replay.exit.clone());
                frame.replayed = true;
                return Ok(started);
            }
        }
        frame.replay = None;
        // SAFETY: `begin_frame` waited for the slot's fence, and its kept recording is dropped.
        if let Some(replaced) = unsafe { frame.reserve_queries(device, plan.timestamps(), plan.statistics())? } {
            self.graph.forget(Resource::Buffer(replaced));
        }
        let entry = prerecorded.then(|| self.graph.states().clone());
        let cmd = if prerecorded { frame.recorder.begin_reusable(device)? } else { frame.recorder.begin(device)? };
        frame.passes = self.graph.record(&ctx, &plan, cmd, &mut frame.scopes(), outputs)?;
        let culled = self.settings.culling.enabled && !self.settings.floor;
        // The further draw classes' buckets (`build_graph` placed them without error).
        let layout = super::response::class_layout(&self.settings, &self.builders.classes);
        let classes = layout.map(|layout| layout.ranges()).unwrap_or_default();
        let cull = &mut self.cull_frames[slot];
        match culled {
            true => cull.recorded(self.settings.culling.buckets(), self.settings.culling.solid_outline, &classes[1..]),
            false => cull.recorded(&[], false, &[]),
        }
        if culled {
            // The frame's counts, read by the host after the fence.
            self.graph.release(device, cmd, &[(Resource::Buffer(cull.stats.raw), Access::HostRead)]);
        }
        // The queries' results, copied on the GPU for the host to read after the fence.
        let results = Resource::Buffer(frame.record_query_copies(device, cmd));
        self.graph.import(results, &[Access::TransferWrite]);
        self.graph.release(device, cmd, &[(results, Access::HostRead)]);
        frame.recorder.end(device)?;
        if let (Some(entry), Some(passes)) = (entry, plan.replay()) {
            let exit = self.graph.states().clone();
            frame.replay = Some(Replay { target: key, entry, exit, passes: passes.to_vec() });
        }
        Ok(started)
    }
}
