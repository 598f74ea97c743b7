//! Blade pass: every blade in one instanced draw, geometry expanded in the vertex shader
//! (vertex pulling, thesis 4.1 Bézier strips, no vertex buffer).

use ash::vk;

use crate::error::Result;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::submission::{self, BladeDraws};
use crate::vk::{pipeline, Device};

/// The blade pipeline.
pub struct BladePass {
    pipeline: vk::Pipeline,
}

impl BladePass {
    /// Build the pipeline for the given attachment formats. Blades are two-sided: no culling.
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
                name: "blades",
                vertex: shaders::BLADE_VERT,
                fragment: shaders::BLADE_FRAG,
                topology: vk::PrimitiveTopology::TRIANGLE_STRIP,
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

    /// The blade pipeline, bound by `record`.
    pub fn pipeline(&self) -> vk::Pipeline {
        self.pipeline
    }

    /// Bind the pipeline and record `draws`: by default one draw call for all blades, one
    /// instance per blade, a strip of `2(S+1)` vertices. `--blades-per-instance K` packs K blades
    /// into each instance (strips joined by degenerate triangles, `bezier::Batching`) to measure
    /// a driver's per-instance overhead; the picture is the same for every K. `meadow overhead`
    /// submits the same blades per cluster, indirectly or from secondaries (`submission`).
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, draws: &BladeDraws) {
        // SAFETY: cmd is recording inside the blade pass's rendering instance; set 0 is bound.
        unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline) };
        submission::record_draws(device, cmd, draws);
    }

    /// Triangles drawn.
    pub fn triangles(scene: &SceneGpu, segments: u32) -> u64 {
        2 * u64::from(segments) * u64::from(scene.blade_count)
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
