//! Cull step 1 (`shaders/cull_count.comp`): one workgroup per ring slot runs the tile tests
//! (frustum, distance, the density LOD's prefix) and the blade tests, and writes the slot's
//! counts per LOD bucket and after each test, and each candidate's verdict. Reads the scene,
//! writes the slot counts and the verdicts.

use ash::vk;

use super::{ring_slots, CullSetup, CullStep};
use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Access, Device};

/// The counting dispatch.
pub struct CullCountPass(CullStep);

impl CullCountPass {
    /// Build the pipeline.
    pub fn new(device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<Self> {
        let read = Access::ComputeShaderRead;
        let uses = vec![
            (scene.tiles.raw, read),
            (scene.depth_pyramid.raw, read),
            (scene.blades.raw, read),
            (scene.heights.raw, read),
            (scene.slot_counts.raw, Access::ComputeShaderWrite),
            (scene.cull_results.raw, Access::ComputeShaderWrite),
            // A block field's verdict counter: atomically read and written.
            (scene.cull_alloc.raw, Access::ComputeShaderRead),
            (scene.cull_alloc.raw, Access::ComputeShaderWrite),
        ];
        Ok(Self(CullStep::new(device, "cull count", shaders::CULL_COUNT_COMP, setup, uses)?))
    }
}

impl Pass for CullCountPass {
    fn name(&self) -> &'static str {
        "cull count"
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
