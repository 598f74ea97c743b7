//! Blade-pose pass (`--eval blade`): a compute dispatch, one invocation per blade, that does the
//! animation once per blade instead of once per vertex — force, keyframe selection, the blend of
//! every level — and writes each level's point, tangent and twist (12 bytes) for the blade pass
//! (`shaders/blade_pose.comp`, `render::scene_gpu::pose_bytes`). Its records are written here
//! and read by the blade pass's vertex shader; the graph orders the two, and this frame's write
//! after the previous frame's reads.

use ash::vk;

use crate::error::Result;
use crate::render::animation::model::{AnimationSet, PassSetup};
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::passes;
use crate::render::shaders;
use crate::vk::{pipeline, Access, Device, Resource};

/// The compute pipeline and the buffers it touches.
pub struct BladePosePass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    animation: vk::DescriptorSet,
    poses: vk::Buffer,
    blade_count: u32,
    reads: [vk::Buffer; 2],
    keyframes: vk::Image,
}

impl BladePosePass {
    /// Build the pipeline on the scene's pipeline layout, writing the records of `set`.
    pub fn new(device: &Device, setup: &PassSetup, set: &AnimationSet) -> Result<Self> {
        let scene = setup.scene;
        Ok(Self {
            pipeline: pipeline::compute(
                device,
                "blade poses",
                shaders::BLADE_POSE_COMP,
                setup.layout,
                setup.constants,
            )?,
            layout: setup.layout,
            animation: set.set,
            poses: set.poses.raw,
            blade_count: scene.blade_count,
            reads: [scene.blades.raw, scene.clusters.raw],
            keyframes: set.keyframes.image.raw,
        })
    }
}

impl Pass for BladePosePass {
    fn name(&self) -> &'static str {
        "blade poses"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .buffer(self.poses, Access::ComputeShaderWrite)
            .buffer(self.reads[0], Access::ComputeShaderRead)
            .buffer(self.reads[1], Access::ComputeShaderRead)
            .uses(Resource::color(self.keyframes), Access::ComputeShaderSampledRead);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        passes::bind_animation_set(device, cmd, self.layout, vk::PipelineBindPoint::COMPUTE, self.animation);
        // SAFETY: cmd is recording outside a rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, self.blade_count.div_ceil(64), 1, 1);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { device.raw.destroy_pipeline(self.pipeline, None) };
    }
}
