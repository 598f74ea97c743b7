//! What passes and the blade responses' passes record with: binding the frame's set
//! (`SET_SCENE`) and the pose records' (`SET_POSES`), and one indirect dispatch per LOD bucket
//! ([`bucket_dispatch`]). Below both `render::animation` and `render::passes`, so a response's
//! passes and the renderer's share them without importing each other.

pub mod blade_dispatch;
pub mod bucket_dispatch;
pub mod pass_set;

pub use blade_dispatch::{BladeDispatch, BladeSource};
pub use pass_set::{PassSet, PassSetDesc, SceneSets};

use ash::vk;

use crate::render::gpu_constants as gpu;
use crate::render::graph::PassContext;
use crate::vk::Device;

/// Bind the pose records' set (`SET_POSES`) at `bind_point`.
pub fn bind_pose_set(
    device: &Device,
    cmd: vk::CommandBuffer,
    layout: vk::PipelineLayout,
    bind_point: vk::PipelineBindPoint,
    set: vk::DescriptorSet,
) {
    // SAFETY: cmd is recording; the set matches the layout's pose set.
    unsafe { device.raw.cmd_bind_descriptor_sets(cmd, bind_point, layout, gpu::SET_POSES, &[set], &[]) };
}

/// Bind both scene sets (the frame's and the pose records' `poses`) and `pipeline` for compute:
/// what the per-blade passes (poses, levels) record before their dispatch.
pub fn bind_blade_compute(
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    (layout, pipeline): (vk::PipelineLayout, vk::Pipeline),
    poses: vk::DescriptorSet,
) {
    bind_blade_sets(ctx, cmd, layout, poses);
    // SAFETY: cmd is recording outside a rendering instance; the pipeline uses `layout`.
    unsafe { ctx.device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline) };
}

/// Bind the frame's and the pose records' sets for a blade compute pass on `layout` (its
/// pipelines are bound by the caller: one per LOD bucket, `bucket_dispatch`).
pub fn bind_blade_sets(
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    layout: vk::PipelineLayout,
    poses: vk::DescriptorSet,
) {
    let device = ctx.device;
    bind_scene_set(device, ctx, cmd, layout, vk::PipelineBindPoint::COMPUTE);
    bind_pose_set(device, cmd, layout, vk::PipelineBindPoint::COMPUTE, poses);
}

/// Bind the frame's set (`SET_SCENE`) at `bind_point`.
pub fn bind_scene_set(
    device: &Device,
    ctx: &PassContext,
    cmd: vk::CommandBuffer,
    layout: vk::PipelineLayout,
    bind_point: vk::PipelineBindPoint,
) {
    // SAFETY: cmd is recording; the set matches the layout's scene set.
    unsafe { device.raw.cmd_bind_descriptor_sets(cmd, bind_point, layout, gpu::SET_SCENE, &[ctx.descriptor_set], &[]) };
}
