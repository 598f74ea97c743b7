//! Relief-grid pass (a block field's): one compute dispatch, first in the frame, that evaluates the
//! relief (a sum of sine waves, `scene::field::Relief`) at every vertex of the terrain grid around
//! O, height and normal (`shaders/relief_grid.comp`). The terrain pass draws the grid from it, the
//! cull's count pass sets each candidate's root on it, and the blades' lighting takes the terrain
//! normal under each root from it: a texel fetch per corner instead of the relief's eight waves
//! per terrain vertex, candidate root and drawn blade. Writes `SceneGpu::relief_grid`; the graph
//! orders this frame's write after the previous frame's reads.

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{pipeline, Access, Device};

/// The compute pipeline and the grid it writes.
pub struct ReliefGridPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    grid: vk::Buffer,
}

impl ReliefGridPass {
    /// Build the pipeline on the scene pipeline layout; `None` for a stored field (its terrain is
    /// the uploaded `heights`).
    pub fn new(
        device: &Device,
        layout: vk::PipelineLayout,
        constants: &[u32],
        scene: &SceneGpu,
    ) -> Result<Option<Self>> {
        let Some(grid) = scene.relief_grid_read() else {
            return Ok(None);
        };
        let pipeline = pipeline::compute(device, "relief grid", shaders::RELIEF_GRID_COMP, layout, constants)?;
        Ok(Some(Self { pipeline, layout, grid }))
    }
}

impl Pass for ReliefGridPass {
    fn name(&self) -> &'static str {
        "relief grid"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.grid, Access::ComputeShaderWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        let vertices = (gpu::FIELD_TERRAIN_CELLS + 1).pow(2);
        // SAFETY: cmd is recording outside a rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, vertices.div_ceil(gpu::RELIEF_GROUP), 1, 1);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None)
        };
    }
}
