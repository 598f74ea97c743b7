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
use crate::render::recording::{PassSet, PassSetDesc};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{image, pipeline, Access, Device, Guard, Resource};

/// The pipeline, its own set per frame in flight (set 0, `PassSet`, written when recorded), the
/// sampler it reads the depth with (nearest, clamped) and the pyramid it writes.
pub struct DepthPyramidPass {
    pipeline: vk::Pipeline,
    sets: PassSet,
    sampler: vk::Sampler,
    pyramid: vk::DescriptorBufferInfo,
}

impl DepthPyramidPass {
    /// Build the pipeline and `frames` sets; `multisampled`: the depth it reads has several
    /// samples per pixel (`--msaa`), of which it takes the farthest (`hiz_ms.comp`).
    pub fn new(device: &Device, scene: &SceneGpu, frames: usize, multisampled: bool) -> Result<Self> {
        let shader = if multisampled { shaders::HIZ_MS_COMP } else { shaders::HIZ_COMP }.code(device.profile);
        let desc = PassSetDesc { name: "depth pyramid", shaders: &[("hiz", shader)], before: &[], push: &[], frames };
        let sets = Guard::new(device, PassSet::unwritten(device, &desc)?);
        let sampler = Guard::new(device, image::clamped_sampler(device, vk::Filter::NEAREST, "depth pyramid sampler")?);
        let pipeline = pipeline::compute(device, "depth pyramid", shader, sets.layout, &[])?;
        let (sets, sampler) = (sets.take(), sampler.take());
        Ok(Self { pipeline, sets, sampler, pyramid: scene.depth_pyramid.descriptor() })
    }
}

impl Pass for DepthPyramidPass {
    fn name(&self) -> &'static str {
        "depth pyramid"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        // Not built on a frame without the occlusion test: the setting off, a frozen culling
        // camera, or a view the terrain provably cannot hide anything in (`render::occlusion`).
        if ctx.uniforms.cull_lod.z & gpu::CULL_OCCLUSION == 0 {
            return None;
        }
        let declaration = Declaration::compute()
            .uses(Resource::depth(ctx.target.depth), Access::ComputeShaderSampledRead)
            .buffer(self.pyramid.buffer, Access::ComputeShaderWrite);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let depth = vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: ctx.target.depth_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // The slot's previous frame has finished (its fence was waited): its set is free.
        let resources = [("depth", Descriptor::Image(depth)), ("Pyramid", Descriptor::Buffer(self.pyramid))];
        self.sets.write(device, ctx.slot, "depth pyramid", &resources)?;
        let groups = gpu::PYRAMID_SIDE / 16;
        // SAFETY: cmd is recording outside a rendering instance; the set matches the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
        }
        self.sets.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        // SAFETY: as above; the set is bound.
        unsafe {
            device.raw.cmd_dispatch(cmd, groups, groups, 1);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            self.sets.destroy(device);
        }
    }
}
