//! Floor reference pass (`--mode floor`): the blades' triangles pre-expanded on the CPU into one
//! vertex buffer (one strip, blades joined by degenerate triangles), transformed and filled with a
//! flat colour. Every other mode's cost can be read as a ratio to this one.

use ash::vk;

use crate::error::Result;
use crate::render::shaders;
use crate::scene::bezier::{self, Batching};
use crate::scene::BladeInstance;
use crate::vk::{pipeline, Buffer, Device};

/// The floor pipeline.
pub struct FloorPass {
    pipeline: vk::Pipeline,
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
    /// Build the pipeline.
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
                name: "floor",
                vertex: shaders::FLOOR_VERT,
                fragment: shaders::FLOOR_FRAG,
                topology: vk::PrimitiveTopology::TRIANGLE_STRIP,
                cull: vk::CullModeFlags::NONE,
                polygon,
                depth_compare: vk::CompareOp::GREATER,
                color_format: color,
                depth_format: depth,
                layout,
                constants,
                vertex_stride: 12,
            },
        )?;
        Ok(Self { pipeline })
    }

    /// The floor pipeline, bound by `record`.
    pub fn pipeline(&self) -> vk::Pipeline {
        self.pipeline
    }

    /// One draw of the whole strip.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, vertices: &Buffer) {
        // SAFETY: cmd is recording inside the blade pass's rendering instance.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw], &[0]);
            device.raw.cmd_draw(cmd, (vertices.size / 12) as u32, 1, 0, 0);
        }
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
