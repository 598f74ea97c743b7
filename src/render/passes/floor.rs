//! Floor reference pass (`--mode floor`, `RenderSettings::floor`): the blades' triangles
//! pre-expanded on the CPU into one vertex buffer (each blade's 2 (segments + 1) strip vertices
//! once) and an index buffer of the same triangles as a list, transformed and filled with a flat
//! colour: the least a driver needs for them, no degenerate joins. Every other mode's cost can be
//! read as a ratio to this one.

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes::{self, PipelineTarget};
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::scene::bezier;
use crate::scene::BladeInstance;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device, Guard};

/// The floor pipeline and its pre-expanded vertices and indices.
pub struct FloorPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    vertices: Buffer,
    indices: Buffer,
    count: u32,
}

/// The pre-expanded positions of every blade vertex (its strip's, in order, each once) and the
/// triangle list over them: the strip's 2 · segments triangles per blade, nothing else.
pub fn expand(blades: &[BladeInstance], segments: u32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let per_blade = bezier::strip_vertices(segments);
    let mut vertices = Vec::with_capacity(blades.len() * per_blade as usize);
    let mut indices = Vec::with_capacity(blades.len() * 6 * segments as usize);
    for (i, blade) in blades.iter().enumerate() {
        let first = i as u32 * per_blade;
        vertices.extend((0..per_blade).map(|v| bezier::strip_vertex(blade, segments, v).to_array()));
        indices.extend((0..2 * segments).flat_map(|k| [first + k, first + k + 1, first + k + 2]));
    }
    (vertices, indices)
}

impl FloorPass {
    /// Expand and upload the blades of `scene` (`segments` per blade) and build the pipeline.
    pub fn new(
        device: &Device,
        target: PipelineTarget,
        constants: &Specialization,
        blades: &[BladeInstance],
        segments: u32,
    ) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let (positions, list) = expand(blades, segments);
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
        let vertices = batch.buffer("floor vertices", &positions, usage, &[Access::VertexAttributeRead])?;
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        // Not submitted yet; then the batch waits for its submission, or never submits.
        let vertices = Guard::new(device, vertices);
        let indices = Guard::new(device, batch.buffer("floor indices", &list, usage, &[Access::IndexRead])?);
        batch.submit()?;
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "floor",
                vertex: shaders::FLOOR_VERT.code(device.profile),
                fragment: shaders::FLOOR_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants: &constants.named(),
                vertex_stride: 12,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        let (vertices, indices, count) = (vertices.take(), indices.take(), list.len() as u32);
        Ok(Self { pipeline, layout: target.layout, vertices, indices, count })
    }
}

impl Pass for FloorPass {
    /// The floor stands in for the blades in reports (`bench` reads the "blades" pass).
    fn name(&self) -> &'static str {
        "blades"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.pipeline, false, false);
        let declaration = Declaration::graphics(rendering).buffer(self.vertices.raw, Access::VertexAttributeRead);
        Some(declaration.buffer(self.indices.raw, Access::IndexRead))
    }

    /// One indexed draw of every triangle.
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        // SAFETY: cmd is recording inside this pass's rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            device.raw.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            device.raw.cmd_draw_indexed(cmd, self.count, 1, 0, 0, 0);
        }
        Ok(())
    }

    fn replay_key(&self, _: &PassContext) -> Option<u64> {
        // One draw of the whole floor.
        Some(0)
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.vertices.destroy(device);
            self.indices.destroy(device);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expansion_holds_each_vertex_once_and_only_the_strips_triangles() {
        let blades = crate::scene::Scene::generate(3, 1).blades;
        let (v, i) = expand(&blades, 2);
        assert_eq!(v.len(), 3 * 6, "2 (segments + 1) vertices a blade, no repeats");
        assert_eq!(i.len(), 3 * 4 * 3, "2 segments = 4 triangles a blade");
        assert_eq!(v[6], bezier::strip_vertex(&blades[1], 2, 0).to_array());
        // The second blade's first triangle, and no triangle spans two blades.
        assert_eq!(&i[12..15], &[6, 7, 8]);
        assert!(i.chunks(3).all(|t| t[0] / 6 == t[2] / 6));
    }
}
