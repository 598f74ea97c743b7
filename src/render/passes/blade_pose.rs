//! Blade-pose pass (`--eval blade`): a compute dispatch, one invocation per blade, that does the
//! animation once per blade instead of once per vertex — force, keyframe selection, the blend of
//! every level — and writes each level's point, tangent and twist (12 bytes) for the blade pass
//! (`shaders/blade_pose.comp`, `render::scene_gpu::pose_bytes`). Its records are written here
//! and read by the blade pass's vertex shader; the graph orders the two, and this frame's write
//! after the previous frame's reads. With the cull it runs after it, indirectly, over the
//! visible list: each drawn blade once, its records by list entry.

use ash::vk;

use crate::error::Result;
use crate::render::animation::model::{AnimationSet, PassSetup};
use crate::render::gpu_constants as gpu;
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
    /// With the cull: its visible list and its `draws` (the indirect dispatch the scan wrote,
    /// `POSE_DISPATCH_WORD`), one invocation per drawn blade.
    culled: Option<(vk::Buffer, vk::Buffer)>,
}

impl BladePosePass {
    /// Build the pipeline on the scene's pipeline layout, writing the records of `set`.
    pub fn new(device: &Device, setup: &PassSetup, set: &AnimationSet) -> Result<Self> {
        let scene = setup.scene;
        let mut constants = setup.constants.to_vec();
        if setup.culled {
            constants[gpu::SPEC_RENDER_FLAGS as usize] |= gpu::FLAG_CULLED;
        }
        Ok(Self {
            pipeline: pipeline::compute(device, "blade poses", shaders::BLADE_POSE_COMP, setup.layout, &constants)?,
            layout: setup.layout,
            animation: set.set,
            poses: set.per_blade.poses.raw,
            blade_count: scene.blade_count,
            reads: [scene.blades.raw, scene.clusters.raw],
            keyframes: set.keyframes.image.raw,
            culled: setup.culled.then_some((scene.visible.raw, scene.draws.raw)),
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
            .buffer(self.reads[0], Access::ComputeShaderSampledRead)
            .buffer(self.reads[1], Access::ComputeShaderRead)
            .uses(Resource::color(self.keyframes), Access::ComputeShaderSampledRead);
        let declaration = match self.culled {
            Some((visible, draws)) => declaration
                .buffer(visible, Access::ComputeShaderSampledRead)
                .buffer(draws, Access::ComputeShaderRead)
                .buffer(draws, Access::IndirectCommandRead),
            None => declaration,
        };
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_blade_compute(ctx, cmd, (self.layout, self.pipeline), self.animation);
        // SAFETY: cmd is recording outside a rendering instance; both sets and the pipeline are bound.
        unsafe {
            match self.culled {
                Some((_, draws)) => {
                    device.raw.cmd_dispatch_indirect(cmd, draws, 4 * u64::from(gpu::POSE_DISPATCH_WORD))
                }
                None => device.raw.cmd_dispatch(cmd, self.blade_count.div_ceil(gpu::POSE_GROUP), 1, 1),
            }
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None)
        };
    }
}
