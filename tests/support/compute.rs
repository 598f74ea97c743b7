//! One compute dispatch for the GPU tests: bind, push, dispatch, make the output buffer visible
//! to the host, submit and wait; and the teardown of what a test shader was run with. Included with `#[path = "support/compute.rs"] mod compute;` by the
//! tests that run a test shader.

use std::sync::Arc;

use ash::vk;
use meadow::vk::{commands, sync, Access, Buffer, Device};

/// Run `pipe` (layout `layout`, sets bound from 0, `push` as compute push constants when not
/// empty) over `groups` workgroups, then make `out` visible to the host; waits.
pub fn dispatch(
    device: &Arc<Device>,
    name: &str,
    (pipe, layout): (vk::Pipeline, vk::PipelineLayout),
    sets: &[vk::DescriptorSet],
    push: &[u8],
    groups: u32,
    out: vk::Buffer,
) -> meadow::Result<()> {
    commands::submit_and_wait(device, name, |cmd| {
        // SAFETY: all objects are live; host writes are visible at submission.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipe);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, sets, &[]);
            if !push.is_empty() {
                device.raw.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, push);
            }
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
        let to_host = sync::buffer_barrier(out, &[Access::ComputeShaderWrite], &[Access::HostRead]);
        sync::cmd_barriers(device, cmd, &[to_host], &[]);
        Ok(())
    })
}

/// Destroy a test shader's descriptor pool, pipeline, layouts and `buffers`.
///
/// # Safety
/// No pending work may use them.
pub unsafe fn teardown(
    device: &Device,
    (pool, pipe, layout, set_layout): (vk::DescriptorPool, vk::Pipeline, vk::PipelineLayout, vk::DescriptorSetLayout),
    buffers: impl IntoIterator<Item = Buffer>,
) {
    // SAFETY: per the contract.
    unsafe {
        device.raw.destroy_descriptor_pool(pool, None);
        device.raw.destroy_pipeline(pipe, None);
        device.raw.destroy_pipeline_layout(layout, None);
        device.raw.destroy_descriptor_set_layout(set_layout, None);
        for buffer in buffers {
            buffer.destroy(device);
        }
    }
}
