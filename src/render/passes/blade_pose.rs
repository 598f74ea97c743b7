//! Blade-pose pass (`--eval blade`): a compute dispatch, one invocation per blade, that does the
//! animation once per blade instead of once per vertex — force, keyframe selection, the blend of
//! every level — and writes each level's point, tangent and twist (12 bytes) for the blade pass
//! (`shaders/blade_pose.comp`, `render::scene_gpu::pose_bytes`).

use ash::vk;

use crate::error::Result;
use crate::render::shaders;
use crate::vk::{pipeline, sync, Access, Buffer, Device};

/// The compute pipeline.
pub struct BladePosePass {
    pipeline: vk::Pipeline,
}

impl BladePosePass {
    /// Build the pipeline on the scene's pipeline layout.
    pub fn new(device: &Device, layout: vk::PipelineLayout, constants: &[u32]) -> Result<Self> {
        Ok(Self { pipeline: pipeline::compute(device, "blade poses", shaders::BLADE_POSE_COMP, layout, constants)? })
    }

    /// Record the dispatch with its barriers: the previous frame's vertex-shader reads of the
    /// records finish before they are overwritten, and the new records are visible to the vertex
    /// shader of this frame. Set 0 must be bound at the compute bind point.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, poses: &Buffer, blade_count: u32) {
        sync::cmd_barriers(
            device,
            cmd,
            // The previous frame read the records in its vertex shader (WAR) and wrote them here
            // (WAW: a memory dependency, not only the execution chain through the reads).
            &[sync::buffer_barrier(
                poses.raw,
                &[Access::VertexShaderStorageRead, Access::ComputeShaderWrite],
                &[Access::ComputeShaderWrite],
            )],
            &[],
        );
        // SAFETY: cmd is recording outside a rendering instance.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, blade_count.div_ceil(64), 1, 1);
        }
        sync::cmd_barriers(
            device,
            cmd,
            &[sync::buffer_barrier(poses.raw, &[Access::ComputeShaderWrite], &[Access::VertexShaderStorageRead])],
            &[],
        );
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
