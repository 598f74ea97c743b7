//! Terrain pass: the height field, 6 vertices per cell pulled from the heights buffer.

use ash::vk;

use crate::error::Result;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::{pipeline, Device};

/// The terrain pipeline.
pub struct TerrainPass {
    pipeline: vk::Pipeline,
}

impl TerrainPass {
    /// Build the pipeline for the given attachment formats.
    pub fn new(
        device: &Device,
        layout: vk::PipelineLayout,
        color: vk::Format,
        depth: vk::Format,
        constants: &[u32],
        polygon: vk::PolygonMode,
    ) -> Result<Self> {
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "terrain",
                vertex: shaders::TERRAIN_VERT,
                fragment: shaders::TERRAIN_FRAG,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon,
                depth_compare: vk::CompareOp::GREATER,
                color_format: color,
                depth_format: depth,
                layout,
                constants,
                vertex_stride: 0,
            },
        )?;
        Ok(Self { pipeline })
    }

    /// The terrain pipeline, bound by `record`.
    pub fn pipeline(&self) -> vk::Pipeline {
        self.pipeline
    }

    /// Draw the terrain; set 0 must be bound.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, scene: &SceneGpu) {
        let vertices = 6 * scene.terrain_cells * scene.terrain_cells;
        // SAFETY: cmd is recording inside the scene's rendering instance.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.raw.cmd_draw(cmd, vertices, 1, 0, 0);
        }
    }

    /// Triangles drawn.
    pub fn triangles(scene: &SceneGpu) -> u64 {
        2 * u64::from(scene.terrain_cells).pow(2)
    }

    /// Destroy the pipeline.
    ///
    /// # Safety
    /// No pending work may use it.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { device.raw.destroy_pipeline(self.pipeline, None) };
    }
}
