//! Barriers declared as accesses (after vk-sync-rs): a resource goes from its previous accesses
//! to its next accesses, and one pure function turns that into a synchronization2 barrier.
//! Also fences and semaphores.

use ash::vk;

use crate::error::{Result, VkContext};
use crate::vk::device::Device;

/// One way the GPU (or host) touches a resource. The stage is part of the access: a keyframe
/// texture sampled in the vertex shader is `VertexShaderSampledRead`, not a generic "shader read".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// No access: the previous contents are discarded (layout UNDEFINED).
    Nothing,
    /// Destination of a copy or clear.
    TransferWrite,
    /// Source of a copy.
    TransferRead,
    /// Read by the host after a fence wait (mapped readback buffers).
    HostRead,
    /// Storage buffer read in the vertex shader (vertex pulling).
    VertexShaderStorageRead,
    /// Uniform buffer read in the vertex shader.
    VertexShaderUniformRead,
    /// Image sampled, or uniform texel buffer fetched, in the vertex shader (keyframe textures,
    /// `buffer::TexelView`s).
    VertexShaderSampledRead,
    /// Image sampled in the fragment shader.
    FragmentShaderSampledRead,
    /// Storage buffer read in the fragment shader.
    FragmentShaderStorageRead,
    /// Storage buffer or image read in a compute shader.
    ComputeShaderRead,
    /// Image sampled, or uniform texel buffer fetched, in a compute shader.
    ComputeShaderSampledRead,
    /// Uniform buffer read in a compute shader.
    ComputeShaderUniformRead,
    /// Storage buffer or image written by a compute shader.
    ComputeShaderWrite,
    /// Indirect draw/dispatch parameters.
    IndirectCommandRead,
    /// Vertex buffer read by fixed-function vertex input.
    VertexAttributeRead,
    /// Index buffer read by fixed-function vertex input.
    IndexRead,
    /// Written as a colour attachment.
    ColorAttachmentWrite,
    /// Read and written as a depth attachment (test and write).
    DepthAttachmentReadWrite,
    /// Read as a depth attachment (test without write): in the attachment layout, so a pass
    /// that only tests follows one that writes with no layout change.
    DepthAttachmentRead,
    /// Handed to the presentation engine.
    Present,
    /// A swapchain image just acquired: contents discarded, and the transition starts at the
    /// colour-output stage where the acquire semaphore is waited, so the two chain.
    Acquired,
}

/// What one access means to synchronization2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AccessInfo {
    /// Pipeline stages that perform the access.
    pub stages: vk::PipelineStageFlags2,
    /// Memory access types.
    pub access: vk::AccessFlags2,
    /// Image layout required by the access.
    pub layout: vk::ImageLayout,
}

impl Access {
    /// Stages, access flags and image layout of this access.
    pub fn info(self) -> AccessInfo {
        use vk::AccessFlags2 as A;
        use vk::ImageLayout as L;
        use vk::PipelineStageFlags2 as S;
        let (stages, access, layout) = match self {
            Access::Nothing => (S::NONE, A::NONE, L::UNDEFINED),
            Access::TransferWrite => (S::COPY | S::CLEAR, A::TRANSFER_WRITE, L::TRANSFER_DST_OPTIMAL),
            Access::TransferRead => (S::COPY, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
            Access::HostRead => (S::HOST, A::HOST_READ, L::GENERAL),
            Access::VertexShaderStorageRead => (S::VERTEX_SHADER, A::SHADER_STORAGE_READ, L::GENERAL),
            Access::VertexShaderUniformRead => (S::VERTEX_SHADER, A::UNIFORM_READ, L::GENERAL),
            Access::VertexShaderSampledRead => (S::VERTEX_SHADER, A::SHADER_SAMPLED_READ, L::SHADER_READ_ONLY_OPTIMAL),
            Access::FragmentShaderSampledRead => {
                (S::FRAGMENT_SHADER, A::SHADER_SAMPLED_READ, L::SHADER_READ_ONLY_OPTIMAL)
            }
            Access::FragmentShaderStorageRead => (S::FRAGMENT_SHADER, A::SHADER_STORAGE_READ, L::GENERAL),
            Access::ComputeShaderRead => (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ, L::GENERAL),
            Access::ComputeShaderSampledRead => {
                (S::COMPUTE_SHADER, A::SHADER_SAMPLED_READ, L::SHADER_READ_ONLY_OPTIMAL)
            }
            Access::ComputeShaderUniformRead => (S::COMPUTE_SHADER, A::UNIFORM_READ, L::GENERAL),
            Access::ComputeShaderWrite => (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, L::GENERAL),
            Access::IndirectCommandRead => (S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ, L::GENERAL),
            Access::VertexAttributeRead => (S::VERTEX_ATTRIBUTE_INPUT, A::VERTEX_ATTRIBUTE_READ, L::GENERAL),
            Access::IndexRead => (S::INDEX_INPUT, A::INDEX_READ, L::GENERAL),
            Access::ColorAttachmentWrite => (
                S::COLOR_ATTACHMENT_OUTPUT,
                A::COLOR_ATTACHMENT_WRITE | A::COLOR_ATTACHMENT_READ,
                L::COLOR_ATTACHMENT_OPTIMAL,
            ),
            Access::DepthAttachmentReadWrite => (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
                L::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            Access::DepthAttachmentRead => (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ,
                L::DEPTH_ATTACHMENT_OPTIMAL,
            ),
            // Presentation is ordered by the semaphore; the barrier only changes the layout.
            Access::Present => (S::NONE, A::NONE, L::PRESENT_SRC_KHR),
            Access::Acquired => (S::COLOR_ATTACHMENT_OUTPUT, A::NONE, L::UNDEFINED),
        };
        AccessInfo { stages, access, layout }
    }

    /// The write part of the access (only writes need to be made available).
    pub fn writes(self) -> vk::AccessFlags2 {
        use vk::AccessFlags2 as A;
        let writes = A::TRANSFER_WRITE
            | A::SHADER_STORAGE_WRITE
            | A::COLOR_ATTACHMENT_WRITE
            | A::DEPTH_STENCIL_ATTACHMENT_WRITE
            | A::HOST_WRITE;
        self.info().access & writes
    }
}

/// Source and destination scopes and layouts of a transition from `previous` to `next` accesses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    /// Stages that must finish (`srcStageMask`).
    pub src_stages: vk::PipelineStageFlags2,
    /// Writes made available (`srcAccessMask`): reads need no availability.
    pub src_access: vk::AccessFlags2,
    /// Stages that wait (`dstStageMask`).
    pub dst_stages: vk::PipelineStageFlags2,
    /// Accesses the memory is made visible to (`dstAccessMask`).
    pub dst_access: vk::AccessFlags2,
    /// Layout before (UNDEFINED discards the contents).
    pub old_layout: vk::ImageLayout,
    /// Layout after.
    pub new_layout: vk::ImageLayout,
}

/// The one function that turns accesses into a barrier.
///
/// The layouts are those of the last access on each side; for an image all accesses of a side
/// must agree (`image_barrier` checks), for a buffer they mean nothing.
pub fn transition(previous: &[Access], next: &[Access]) -> Transition {
    let mut t = Transition {
        src_stages: vk::PipelineStageFlags2::NONE,
        src_access: vk::AccessFlags2::NONE,
        dst_stages: vk::PipelineStageFlags2::NONE,
        dst_access: vk::AccessFlags2::NONE,
        old_layout: vk::ImageLayout::UNDEFINED,
        new_layout: vk::ImageLayout::UNDEFINED,
    };
    for access in previous {
        let info = access.info();
        t.src_stages |= info.stages;
        t.src_access |= access.writes();
        t.old_layout = info.layout;
    }
    for access in next {
        let info = access.info();
        t.dst_stages |= info.stages;
        t.dst_access |= info.access;
        t.new_layout = info.layout;
    }
    t
}

/// Whether all `accesses` use one image layout (a trailing `Nothing` discards the contents: the
/// old layout is then UNDEFINED, whatever the accesses before it used).
pub fn one_layout(accesses: &[Access]) -> bool {
    let accesses = match accesses.split_last() {
        Some((Access::Nothing, rest)) => rest,
        _ => accesses,
    };
    accesses.windows(2).all(|w| w[0].info().layout == w[1].info().layout)
}

/// A synchronization2 image barrier over `range` for the transition `previous → next`.
pub fn image_barrier(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    previous: &[Access],
    next: &[Access],
) -> vk::ImageMemoryBarrier2<'static> {
    debug_assert!(one_layout(previous), "previous accesses disagree on the layout: {previous:?}");
    debug_assert!(one_layout(next), "next accesses disagree on the layout: {next:?}");
    let t = transition(previous, next);
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(t.src_stages)
        .src_access_mask(t.src_access)
        .dst_stage_mask(t.dst_stages)
        .dst_access_mask(t.dst_access)
        .old_layout(t.old_layout)
        .new_layout(t.new_layout)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range)
}

/// A synchronization2 buffer barrier over the whole buffer for `previous → next`.
pub fn buffer_barrier(buffer: vk::Buffer, previous: &[Access], next: &[Access]) -> vk::BufferMemoryBarrier2<'static> {
    let t = transition(previous, next);
    vk::BufferMemoryBarrier2::default()
        .src_stage_mask(t.src_stages)
        .src_access_mask(t.src_access)
        .dst_stage_mask(t.dst_stages)
        .dst_access_mask(t.dst_access)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .buffer(buffer)
        .offset(0)
        .size(vk::WHOLE_SIZE)
}

/// Record one `vkCmdPipelineBarrier2` with the given barriers.
pub fn cmd_barriers(
    device: &Device,
    cmd: vk::CommandBuffer,
    buffers: &[vk::BufferMemoryBarrier2],
    images: &[vk::ImageMemoryBarrier2],
) {
    if buffers.is_empty() && images.is_empty() {
        return;
    }
    let dependency = vk::DependencyInfo::default().buffer_memory_barriers(buffers).image_memory_barriers(images);
    // SAFETY: cmd is recording; barriers reference live resources.
    unsafe { device.raw.cmd_pipeline_barrier2(cmd, &dependency) };
}

/// Create a named fence.
pub fn fence(device: &Device, signaled: bool, name: &str) -> Result<vk::Fence> {
    let flags = if signaled { vk::FenceCreateFlags::SIGNALED } else { vk::FenceCreateFlags::empty() };
    // SAFETY: valid create info.
    let fence = unsafe { device.raw.create_fence(&vk::FenceCreateInfo::default().flags(flags), None) }
        .vk("vkCreateFence")
        .map(super::live::created)?;
    device.set_name(fence, name);
    Ok(fence)
}

/// Create a named binary semaphore.
pub fn semaphore(device: &Device, name: &str) -> Result<vk::Semaphore> {
    // SAFETY: valid create info.
    let semaphore = unsafe { device.raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
        .vk("vkCreateSemaphore")
        .map(super::live::created)?;
    device.set_name(semaphore, name);
    Ok(semaphore)
}

/// Wait for a fence without a time limit.
pub fn wait_fence(device: &Device, fence: vk::Fence) -> Result<()> {
    // SAFETY: the fence belongs to this device.
    unsafe { device.raw.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences")
}

#[cfg(test)]
mod tests {
    use super::*;
    use vk::AccessFlags2 as A;
    use vk::ImageLayout as L;
    use vk::PipelineStageFlags2 as S;

    // Cases after the Khronos synchronization examples.

    #[test]
    fn upload_then_sample_in_fragment_shader() {
        let t = transition(&[Access::TransferWrite], &[Access::FragmentShaderSampledRead]);
        assert_eq!(t.src_stages, S::COPY | S::CLEAR);
        assert_eq!(t.src_access, A::TRANSFER_WRITE);
        assert_eq!(t.dst_stages, S::FRAGMENT_SHADER);
        assert_eq!(t.dst_access, A::SHADER_SAMPLED_READ);
        assert_eq!((t.old_layout, t.new_layout), (L::TRANSFER_DST_OPTIMAL, L::SHADER_READ_ONLY_OPTIMAL));
    }

    #[test]
    fn keyframe_texture_waits_in_the_vertex_stage() {
        let t = transition(&[Access::TransferWrite], &[Access::VertexShaderSampledRead]);
        assert_eq!(t.dst_stages, S::VERTEX_SHADER);
    }

    #[test]
    fn read_after_read_makes_nothing_available() {
        let t = transition(&[Access::VertexShaderStorageRead], &[Access::TransferWrite]);
        assert_eq!(t.src_access, A::NONE, "a WAR hazard needs only an execution dependency");
        assert_eq!(t.src_stages, S::VERTEX_SHADER);
    }

    #[test]
    fn discard_contents_from_nothing() {
        let t = transition(&[Access::Nothing], &[Access::ColorAttachmentWrite]);
        assert_eq!(t.src_stages, S::NONE);
        assert_eq!(t.old_layout, L::UNDEFINED);
        assert_eq!(t.new_layout, L::COLOR_ATTACHMENT_OPTIMAL);
        assert!(t.dst_access.contains(A::COLOR_ATTACHMENT_WRITE));
    }

    #[test]
    fn acquired_image_chains_with_the_acquire_semaphore() {
        // The semaphore wait happens at COLOR_ATTACHMENT_OUTPUT: the layout transition must start
        // there, or it could run before the presentation engine released the image.
        let t = transition(&[Access::Acquired], &[Access::ColorAttachmentWrite]);
        assert_eq!(t.src_stages, S::COLOR_ATTACHMENT_OUTPUT);
        assert_eq!(t.old_layout, L::UNDEFINED);
        let p = transition(&[Access::ColorAttachmentWrite], &[Access::Present]);
        assert_eq!((p.src_access, p.new_layout), (A::COLOR_ATTACHMENT_WRITE, L::PRESENT_SRC_KHR));
    }

    #[test]
    fn render_then_copy_to_host() {
        let t = transition(&[Access::ColorAttachmentWrite], &[Access::TransferRead]);
        assert_eq!(t.src_stages, S::COLOR_ATTACHMENT_OUTPUT);
        assert_eq!(t.src_access, A::COLOR_ATTACHMENT_WRITE);
        assert_eq!(t.dst_access, A::TRANSFER_READ);
        let h = transition(&[Access::TransferWrite], &[Access::HostRead]);
        assert_eq!((h.dst_stages, h.dst_access), (S::HOST, A::HOST_READ));
    }

    #[test]
    fn depth_tested_without_write_after_a_depth_write() {
        // Blended plants after the blades: a read after write in the same layout, and the next
        // frame's depth write waits for the test (write after read, nothing to make available).
        let t = transition(&[Access::DepthAttachmentReadWrite], &[Access::DepthAttachmentRead]);
        assert_eq!(t.src_access, A::DEPTH_STENCIL_ATTACHMENT_WRITE);
        assert_eq!(t.dst_access, A::DEPTH_STENCIL_ATTACHMENT_READ);
        assert_eq!((t.old_layout, t.new_layout), (L::DEPTH_ATTACHMENT_OPTIMAL, L::DEPTH_ATTACHMENT_OPTIMAL));
        let war = transition(&[Access::DepthAttachmentRead], &[Access::DepthAttachmentReadWrite]);
        assert_eq!(war.src_access, A::NONE);
        assert!(war.src_stages.contains(S::LATE_FRAGMENT_TESTS));
        assert_eq!(Access::DepthAttachmentRead.writes(), A::NONE);
    }

    #[test]
    fn compute_write_then_vertex_and_indirect_read() {
        let t =
            transition(&[Access::ComputeShaderWrite], &[Access::VertexShaderStorageRead, Access::IndirectCommandRead]);
        assert_eq!(t.src_access, A::SHADER_STORAGE_WRITE);
        assert_eq!(t.dst_stages, S::VERTEX_SHADER | S::DRAW_INDIRECT);
        assert_eq!(t.dst_access, A::SHADER_STORAGE_READ | A::INDIRECT_COMMAND_READ);
    }
}
