//! The line pipeline of the debug views drawn over the finished picture (the cluster bounds, the
//! wind's arrows): a vertex shader that pulls its own vertices from set 0 and a push constant,
//! `shaders/debug/lines.frag` for the colour, on a pipeline layout of its own, drawn over
//! everything (depth ALWAYS: the grass would hide most of what they show).

use ash::vk;

use crate::error::Result;
use crate::render::graph::PassContext;
use crate::render::passes::{self, PipelineTarget};
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::{pipeline, Device, Guard};

/// A debug view's line pipeline and its layout.
pub struct DebugLines {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
}

impl DebugLines {
    /// The pipeline `name` of `vertex` (SPIR-V) on a layout of the scene's set 0 and a vertex
    /// push constant of `push_bytes`.
    pub fn new(
        device: &Device,
        name: &str,
        vertex: &[u8],
        (set_layout, target): (vk::DescriptorSetLayout, PipelineTarget),
        (constants, push_bytes): (&Specialization, u32),
    ) -> Result<Self> {
        let range = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::VERTEX, offset: 0, size: push_bytes };
        let layout_name = format!("{name} layout");
        let layout = Guard::new(device, pipeline::layout(device, &layout_name, &[set_layout], &[range])?);
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name,
                vertex,
                fragment: shaders::DEBUG_LINES_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::LINE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: vk::PolygonMode::FILL,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: *layout,
                constants: &constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        Ok(Self { pipeline, layout: layout.take() })
    }

    /// The pipeline (a pass's rendering instance names it).
    pub fn pipeline(&self) -> vk::Pipeline {
        self.pipeline
    }

    /// Bind the pipeline with set 0, push `push` and draw `vertices` vertices.
    pub fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer, push: &[u8], vertices: u32) {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        // SAFETY: cmd is recording inside the pass's rendering instance; set 0 is bound, and the
        // layout's vertex push range holds `push`.
        unsafe {
            device.raw.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, push);
            device.raw.cmd_draw(cmd, vertices, 1, 0, 0);
        }
    }

    /// Destroy the pipeline and its layout.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
        }
    }
}
