//! Depth pyramid (Hi-Z) pass (`shaders/hiz.comp`): after the terrain, one dispatch reduces this
//! frame's depth to three levels of farthest depth over the picture, which the cull tests tiles
//! and blades against (`CULL_OCCLUSION`, `shaders/cull.glsl`). It reads the target's depth image
//! (sampled, then back to an attachment for the blades: the graph's barriers), so its set, one
//! per frame in flight, is pointed at the depth view of the frame being recorded: that set's
//! previous use ended with the slot's fence.

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::descriptor::{self, Binding, Resource as Descriptor};
use crate::vk::{pipeline, Access, Device, Resource};

/// The pipeline, its own set per frame in flight, and the pyramid it writes.
pub struct DepthPyramidPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    sampler: vk::Sampler,
    pyramid: vk::DescriptorBufferInfo,
}

fn bindings() -> [Binding; 2] {
    let cs = vk::ShaderStageFlags::COMPUTE;
    [
        Binding { binding: 0, kind: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages: cs },
        Binding { binding: 1, kind: vk::DescriptorType::STORAGE_BUFFER, stages: cs },
    ]
}

impl DepthPyramidPass {
    /// Build the pipeline and `frames` sets; `multisampled`: the depth it reads has several
    /// samples per pixel (`--msaa`), of which it takes the farthest (`hiz_ms.comp`).
    pub fn new(device: &Device, scene: &SceneGpu, frames: usize, multisampled: bool) -> Result<Self> {
        let mut pass = Self {
            pipeline: vk::Pipeline::null(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            sets: Vec::new(),
            sampler: vk::Sampler::null(),
            pyramid: scene.depth_pyramid.descriptor(),
        };
        if let Err(e) = pass.build(device, frames, multisampled) {
            // SAFETY: nothing was submitted with the pass; null handles are ignored.
            unsafe { Box::new(pass).destroy(device) };
            return Err(e);
        }
        Ok(pass)
    }

    fn build(&mut self, device: &Device, frames: usize, multisampled: bool) -> Result<()> {
        self.set_layout = descriptor::set_layout(device, "depth pyramid set layout", &bindings())?;
        self.layout = pipeline::layout(device, "depth pyramid layout", &[self.set_layout], &[])?;
        let (pool, sets) =
            descriptor::allocate_sets(device, "depth pyramid sets", self.set_layout, &bindings(), frames as u32)?;
        (self.pool, self.sets) = (pool, sets);
        self.sampler = crate::vk::image::clamped_sampler(device, vk::Filter::NEAREST, "depth pyramid sampler")?;
        let shader = if multisampled { shaders::HIZ_MS_COMP } else { shaders::HIZ_COMP };
        self.pipeline = pipeline::compute(device, "depth pyramid", shader, self.layout, &[])?;
        Ok(())
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
        let set = self.sets[ctx.slot];
        let depth = vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: ctx.target.depth_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // The slot's previous frame has finished (its fence was waited): its set is free.
        descriptor::write(
            device,
            set,
            &[
                (0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, Descriptor::Image(depth)),
                (1, vk::DescriptorType::STORAGE_BUFFER, Descriptor::Buffer(self.pyramid)),
            ],
        );
        let groups = gpu::PYRAMID_SIDE / 16;
        // SAFETY: cmd is recording outside a rendering instance; the set matches the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.layout, 0, &[set], &[]);
            device.raw.cmd_dispatch(cmd, groups, groups, 1);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op; the sets go with the pool.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            crate::vk::live::destroyed(self.set_layout);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
