//! The flowers' pass: after the blades, each of the flowers' buckets drawn with
//! `vkCmdDrawIndexedIndirect` from the cull's draws (`draw_class::draw_word`), one pipeline
//! (`shaders/flowers/flower.vert`, `flower.frag`) and one index list for both
//! (`flower_indices`: the vertex codes say which bucket's flower a vertex belongs to).
//!
//! Reads: the cull's visible list and draws, the stored blades (a block field's block), the
//! ground, the pose records (the stems' poses, by entry) and its index list. Writes: the scene's
//! colour and depth.

use ash::vk;

use super::flower_indices;
use crate::error::Result;
use crate::render::draw_class::{draw_word, ClassSetup};
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes;
use crate::render::recording;
use crate::render::shaders;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device, Guard};

/// The pipeline, its index list and what it reads.
pub struct FlowerPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    indices: Buffer,
    draws: vk::Buffer,
    poses: vk::DescriptorSet,
    /// Buffers the vertex shader reads, and how.
    reads: Vec<(vk::Buffer, Access)>,
    /// The flowers' first bucket.
    first_bucket: u32,
}

impl FlowerPass {
    /// Build the pipeline on the scene's layout and upload the index list.
    pub fn new(device: &Device, setup: &ClassSetup) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let list = flower_indices(setup.blades_per_instance);
        let usage = vk::BufferUsageFlags::INDEX_BUFFER;
        let indices = batch.buffer("flower indices", &list, usage, &[Access::IndexRead])?;
        // Not submitted yet: the batch waits for its submission, or never submits.
        let indices = Guard::new(device, indices);
        batch.submit()?;
        let target = setup.target;
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "flowers",
                vertex: shaders::FLOWER_VERT.code(device.profile),
                fragment: shaders::FLOWER_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                // Petals and stems are seen from both sides.
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants: &setup.constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        let scene = setup.scene;
        let fetch = device.profile.vertex_fetch();
        let [poses, levels] = setup.poses.1;
        // The shader names the pose set's both buffers (synchronization validation counts static
        // use), the blades and the ground through the shared headers.
        let reads = vec![
            (scene.visible.raw, fetch),
            (scene.blades.raw, fetch),
            (scene.clusters.raw, Access::VertexShaderStorageRead),
            (scene.ground.texels.raw, fetch),
            (scene.ground.cover.0.raw, fetch),
            (poses, Access::VertexShaderStorageRead),
            (levels, fetch),
        ];
        Ok(Self {
            pipeline,
            layout: target.layout,
            indices: indices.take(),
            draws: scene.draws.raw,
            poses: setup.poses.0,
            reads,
            first_bucket: setup.first_bucket,
        })
    }
}

impl Pass for FlowerPass {
    fn name(&self) -> &'static str {
        "flowers"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let rendering = passes::scene_rendering(ctx, self.pipeline, true, false);
        let declaration = self.reads.iter().fold(Declaration::graphics(rendering), |d, &(b, a)| d.buffer(b, a));
        let declaration = declaration.buffer(self.draws, Access::IndirectCommandRead);
        Some(declaration.buffer(self.indices.raw, Access::IndexRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        recording::bind_pose_set(device, cmd, self.layout, vk::PipelineBindPoint::GRAPHICS, self.poses);
        // SAFETY: cmd is recording inside this pass's rendering instance; both sets and the
        // pipeline are bound; the scan wrote both buckets' draws before this pass (the graph's
        // barrier).
        unsafe { device.raw.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32) };
        for bucket in 0..2 {
            let (offset, stride) = draw_word(self.first_bucket + bucket);
            // SAFETY: as above.
            unsafe { device.raw.cmd_draw_indexed_indirect(cmd, self.draws, offset, 1, stride) };
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.indices.destroy(device);
        }
    }
}
