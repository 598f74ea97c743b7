//! What the renderer offers passes defined outside the library (a simulation, a bake, a test's
//! pass): adding them to every frame, temporal pairs, imports of their resources, the clock, and
//! a set 0 of their own with their own frame uniforms (`FrameInstance`: a bake's camera).

use ash::vk;

use super::Renderer;
use crate::error::Result;
use crate::render::graph::{Pass, PassUniforms, Temporal, TemporalPair};
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::SetLayout;
use crate::vk::{Access, Destroy, Device, Guard, Resource};

/// A set-0 instance of a pass's own, one per frame in flight: each points at the scene and that
/// frame's forces as the frame's own set 0 does, and at the pass's own `FrameUniforms` block
/// (`uniforms`), which the pass fills through `Pass::uniforms` (e.g.
/// `ctx.uniforms.with_orthographic(&camera)`): a bake renders with its own camera and never sees
/// the main one. Made by `Renderer::frame_instance`.
pub struct FrameInstance {
    /// The instance's `FrameUniforms`, one block per frame in flight.
    pub uniforms: PassUniforms,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
}

impl Destroy for FrameInstance {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { FrameInstance::destroy(self, device) };
    }
}

impl FrameInstance {
    /// The set 0 of frame slot `slot`.
    pub fn set(&self, slot: usize) -> vk::DescriptorSet {
        self.sets[slot]
    }

    /// Destroy it (the sets go with the pool).
    ///
    /// # Safety
    /// No pending work may use it.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            self.uniforms.destroy(device);
        }
    }
}

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

    /// The layout of set 0 (`SET_SCENE`), for the pipeline layout of a pass that binds a
    /// `FrameInstance` or the frame's own set 0.
    pub fn frame_set_layout(&self) -> &SetLayout {
        &self.layouts.scene
    }

    /// A set 0 of `name`'s own with its own frame uniforms (`FrameInstance`), for this renderer's
    /// scene and frames; the caller destroys it once the frames that used it are done (after
    /// `wait_all_frames`, or behind `defer`).
    pub fn frame_instance(&self, name: &str) -> Result<FrameInstance> {
        let device = &*self.device;
        let slots = self.settings.frames_in_flight;
        let size = std::mem::size_of::<FrameUniforms>() as u64;
        let uniforms = Guard::new(device, PassUniforms::new(device, &format!("{name} frame"), size, slots)?);
        let (pool, sets) = self.layouts.scene.allocate(device, &format!("{name} frame sets"), slots as u32)?;
        let instance = Guard::new(device, FrameInstance { uniforms: uniforms.take(), pool, sets });
        for slot in 0..slots {
            let mut own = super::frame_bindings(&self.forces, slot);
            let block = crate::vk::descriptor::Resource::Buffer(instance.uniforms.descriptor(slot));
            own.extend(crate::render::layouts::frame_resources(block));
            let set = instance.sets[slot];
            self.scene_gpu().write_descriptors(device, &self.layouts.scene, set, &own)?;
        }
        Ok(instance.take())
    }

    /// Set the simulation's fixed step (`FrameClock::dt`, seconds) of the next frames.
    pub fn set_time_step(&mut self, dt: f32) {
        self.time_step = dt;
    }
}
