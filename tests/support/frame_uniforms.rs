//! The frame uniforms a test shader reads, uploaded. Included with
//! `#[path = "support/frame_uniforms.rs"] mod frame_uniforms;` by the keyframe tests.

use std::sync::Arc;

use ash::vk;
use meadow::render::uniforms::FrameUniforms;
use meadow::vk::{Buffer, BufferDesc, Device};

/// `uniforms` in a host-written uniform buffer named `name`.
pub fn upload(device: &Arc<Device>, name: &str, uniforms: &FrameUniforms) -> meadow::Result<Buffer> {
    let size = std::mem::size_of::<FrameUniforms>() as u64;
    let desc = BufferDesc::upload(name, size, vk::BufferUsageFlags::UNIFORM_BUFFER);
    Buffer::with_data(device, &desc, bytemuck::bytes_of(uniforms))
}
