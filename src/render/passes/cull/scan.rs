//! Cull step 2 (`shaders/cull_scan.comp`): one workgroup turns the slot counts into offsets (a
//! prefix sum in slot order, near to far), writes one indirect draw per LOD bucket and the
//! frame's counts into the frame's host-visible buffer (read after its fence). Every word it
//! writes is written whole each frame: there is no counter to clear.

use ash::vk;

use super::{CullSetup, CullStep};
use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{Access, Device};

/// The scan dispatch.
pub struct CullScanPass {
    step: CullStep,
    /// Each frame's host-visible counts, by frame slot.
    frame_stats: Vec<vk::Buffer>,
}

impl CullScanPass {
    /// Build the pipeline.
    pub fn new(device: &Device, setup: &CullSetup, scene: &SceneGpu) -> Result<Self> {
        let uses = vec![
            (scene.slot_counts.raw, Access::ComputeShaderRead),
            (scene.slot_counts.raw, Access::ComputeShaderWrite),
            (scene.draws.raw, Access::ComputeShaderWrite),
        ];
        let step = CullStep::new(device, "cull scan", shaders::CULL_SCAN_COMP, setup, uses)?;
        Ok(Self { step, frame_stats: setup.frame_stats.clone() })
    }
}

impl Pass for CullScanPass {
    fn name(&self) -> &'static str {
        "cull scan"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        Some(self.step.declare(&[(self.frame_stats[ctx.slot], Access::ComputeShaderWrite)]))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        self.step.record(ctx, cmd, 1);
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.step.destroy(device) };
    }
}
