//! Cull step 0, a block field's only (`vkCmdFillBuffer`): clear the counter of verdicts the
//! count pass's slots take room from (`shaders/cull_count.comp`). A transfer, ordered before the
//! count pass by the graph's barrier: never cleared inside a shader.

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::scene_gpu::SceneGpu;
use crate::vk::{Access, Device};

/// The fill of the counter.
pub struct CullClearPass {
    alloc: vk::Buffer,
}

impl CullClearPass {
    /// Clear `scene`'s verdict counter each frame.
    pub fn new(scene: &SceneGpu) -> Self {
        Self { alloc: scene.cull_alloc.raw }
    }
}

impl Pass for CullClearPass {
    fn name(&self) -> &'static str {
        "cull clear"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.alloc, Access::TransferWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        // SAFETY: cmd is recording outside a rendering instance; the graph ordered the fill.
        unsafe { ctx.device.raw.cmd_fill_buffer(cmd, self.alloc, 0, 4, 0) };
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, _: &Device) {}
}
