//! Floor reference pass (`--mode floor`, `RenderSettings::floor`): the blades' triangles pre-expanded on the CPU into one
//! vertex buffer (one strip, blades joined by degenerate triangles), transformed and filled with a
//! flat colour. Every other mode's cost can be read as a ratio to this one.

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes::{self, PipelineTarget};
use crate::render::shaders;
use crate::scene::bezier::{self, Batching};
use crate::scene::BladeInstance;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device};

/// The floor pipeline and its pre-expanded vertices.
pub struct FloorPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    vertices: Buffer,
    count: u32,
}

/// The pre-expanded positions of every blade vertex, in the batched strip order.
pub fn expand(blades: &[BladeInstance], segments: u32) -> Vec<[f32; 3]> {
    let batching = Batching::new(segments, 2);
    let per_blade = batching.stride;
    let mut out = Vec::with_capacity(blades.len() * per_blade as usize);
    for blade in blades {
        for v in 0..per_blade {
            let (_, strip) = batching.vertex(segments, v);
            out.push(bezier::strip_vertex(blade, segments, strip).to_array());
        }
    }
    out
}

impl FloorPass {
    /// Expand and upload the blades of `scene` (`segments` per blade) and build the pipeline.
    pub fn new(
        device: &Device,
        target: PipelineTarget,
        constants: &[u32],
        blades: &[BladeInstance],
        segments: u32,
    ) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let vertices =
            batch.buffer("floor vertices", &expand(blades, segments), usage, &[Access::VertexAttributeRead])?;
        if let Err(e) = batch.submit() {
            // SAFETY: the batch waited for its submission, or never submitted.
            unsafe { vertices.destroy(device) };
            return Err(e);
        }
        let built = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "floor",
                vertex: shaders::FLOOR_VERT,
                fragment: shaders::FLOOR_FRAG,
                topology: vk::PrimitiveTopology::TRIANGLE_STRIP,
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants,
                vertex_stride: 12,
            },
        );
        match built {
            Ok(pipeline) => {
                let count = (vertices.size / 12) as u32;
                Ok(Self { pipeline, layout: target.layout, vertices, count })
            }
            Err(e) => {
                // SAFETY: the upload completed; nothing else uses the buffer.
                unsafe { vertices.destroy(device) };
                Err(e)
            }
        }
    }
}

impl Pass for FloorPass {
    /// The floor stands in for the blades in reports (`bench` reads the "blades" pass).
    fn name(&self) -> &'static str {
        "blades"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.pipeline, false, false);
        Some(Declaration::graphics(rendering).buffer(self.vertices.raw, Access::VertexAttributeRead))
    }

    /// One draw of the whole strip.
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        // SAFETY: cmd is recording inside this pass's rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            device.raw.cmd_draw(cmd, self.count, 1, 0, 0);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            device.raw.destroy_pipeline(self.pipeline, None);
            self.vertices.destroy(device);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expansion_matches_the_vertex_shader_layout() {
        let blades = crate::scene::Scene::generate(3, 1).blades;
        let v = expand(&blades, 2);
        assert_eq!(v.len(), 3 * 8);
        // Repeated first and last vertices join the blades.
        assert_eq!(v[0], v[1]);
        assert_eq!(v[6], v[7]);
        assert_eq!(v[1], bezier::strip_vertex(&blades[0], 2, 0).to_array());
        assert_eq!(v[9], bezier::strip_vertex(&blades[1], 2, 0).to_array());
    }
}
