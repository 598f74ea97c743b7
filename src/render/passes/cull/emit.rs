//! Cull step 3 (`shaders/cull_emit.comp`): one workgroup per ring slot reads the count pass's
//! verdicts and writes each drawn blade (its index and its LOD fade and widening) into the
//! visible list at its bucket's base plus its slot's offset plus its rank in the slot: the same
//! list on every run and thread count, buckets then slots near to far.

use ash::vk;

use super::{ring_slots, CullSetup, CullStep};
use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Access, Device};

/// The emitting dispatch.
pub struct CullEmitPass(CullStep);

impl CullEmitPass {
    /// Build the pipeline.
    pub fn new(device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<Self> {
        let read = Access::ComputeShaderRead;
        let uses = vec![
            (scene.tiles.raw, read),
            (scene.depth_pyramid.raw, read),
            (scene.heights.raw, read),
            (scene.cull_results.raw, read),
            (scene.cull_alloc.raw, read),
            (scene.slot_counts.raw, read),
            (scene.draws.raw, read),
            (scene.visible.raw, Access::ComputeShaderWrite),
        ];
        Ok(Self(CullStep::new(device, "cull emit", shaders::CULL_EMIT_COMP, setup, uses)?))
    }
}

impl Pass for CullEmitPass {
    fn name(&self) -> &'static str {
        "cull emit"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(self.0.declare(&[]))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        self.0.record(ctx, cmd, ring_slots(ctx));
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.0.destroy(device) };
    }
}
