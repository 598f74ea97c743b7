//! Depth pyramid (Hi-Z) pass (`shaders/depth_pyramid/hiz.comp`): after the terrain, one dispatch reduces this
//! frame's depth to three levels of farthest depth over the picture, which the cull tests tiles
//! and blades against (`CULL_OCCLUSION`, `shaders/cull/cull.glsl`). It reads the target's depth image
//! (sampled, then back to an attachment for the blades: the graph's barriers), so its set, one
//! per frame in flight, is pointed at the depth view of the frame being recorded: that set's
//! previous use ended with the slot's fence.

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes::FrameSets;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{pipeline, Access, Device, Guard, Resource};

/// The pipeline, its own set per frame in flight (`FrameSets`), and the pyramid it writes.
pub struct DepthPyramidPass {
    pipeline: vk::Pipeline,
    sets: FrameSets,
    pyramid: vk::DescriptorBufferInfo,
}

impl DepthPyramidPass {
    /// Build the pipeline and `frames` sets; `multisampled`: the depth it reads has several
    /// samples per pixel (`--msaa`), of which it takes the farthest (`hiz_ms.comp`).
    pub fn new(device: &Device, scene: &SceneGpu, frames: usize, multisampled: bool) -> Result<Self> {
        let shader = if multisampled { shaders::HIZ_MS_COMP } else { shaders::HIZ_COMP }.code(device.profile);
        let sets = Guard::new(device, FrameSets::new(device, "depth pyramid", &[("hiz", shader)], frames)?);
        let pipeline = pipeline::compute(device, "depth pyramid", shader, sets.layout, &[])?;
        Ok(Self { pipeline, sets: sets.take(), pyramid: scene.depth_pyramid.descriptor() })
    }
}

impl Pass for DepthPyramidPass {
    fn name(&self) -> &'static str {
        "depth pyramid"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .uses(Resource::depth(ctx.target.depth), Access::ComputeShaderSampledRead)
            .buffer(self.pyramid.buffer, Access::ComputeShaderWrite);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let set = self.sets.sets[ctx.slot];
        let depth = vk::DescriptorImageInfo {
            sampler: self.sets.sampler,
            image_view: ctx.target.depth_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // The slot's previous frame has finished (its fence was waited): its set is free.
        let resources = [(0, Descriptor::Image(depth)), (1, Descriptor::Buffer(self.pyramid))];
        self.sets.set_layout.write(device, set, "depth pyramid set", &resources)?;
        let groups = gpu::PYRAMID_SIDE / 16;
        // SAFETY: cmd is recording outside a rendering instance; the set matches the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.sets.layout, 0, &[set], &[]);
            device.raw.cmd_dispatch(cmd, groups, groups, 1);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.sets.destroy(device);
        }
    }
}
