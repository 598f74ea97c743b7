//! Command pools and buffers, and one-shot submissions used at start-up (uploads, readbacks in
//! tests). Frame loops never use `submit_and_wait`: they wait on their own frame fence.

use ash::vk;

use crate::error::{Result, VkContext};
use crate::vk::device::Device;
use crate::vk::guard::Guard;
use crate::vk::sync;

/// A command pool with one primary command buffer.
pub struct CommandRecorder {
    /// The pool.
    pub pool: vk::CommandPool,
    /// Its command buffer.
    pub cmd: vk::CommandBuffer,
}

impl CommandRecorder {
    /// Create a pool on the main queue family and allocate one primary command buffer.
    pub fn new(device: &Device, name: &str) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: valid create info.
        let pool =
            super::live::created(unsafe { device.raw.create_command_pool(&info, None) }.vk("vkCreateCommandPool")?);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: pool is valid.
        let cmd = match unsafe { device.raw.allocate_command_buffers(&alloc) } {
            Ok(buffers) => buffers[0],
            Err(result) => {
                // SAFETY: unused pool.
                unsafe {
                    super::live::destroyed(pool);
                    device.raw.destroy_command_pool(pool, None)
                };
                return Err(crate::error::Error::vulkan("vkAllocateCommandBuffers", result));
            }
        };
        device.set_name(pool, &format!("{name} pool"));
        device.set_name(cmd, name);
        Ok(Self { pool, cmd })
    }

    /// Reset the pool (its command buffer must not be pending) and begin a one-time recording.
    pub fn begin(&self, device: &Device) -> Result<vk::CommandBuffer> {
        // SAFETY: the caller waited for the buffer's last submission.
        unsafe {
            device.raw.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty()).vk("vkResetCommandPool")?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.raw.begin_command_buffer(self.cmd, &begin).vk("vkBeginCommandBuffer")?;
        }
        Ok(self.cmd)
    }

    /// Reset the pool and begin a recording that may be submitted again and again (each
    /// submission after the previous one completed).
    pub fn begin_reusable(&self, device: &Device) -> Result<vk::CommandBuffer> {
        // SAFETY: the caller waited for the buffer's last submission.
        unsafe {
            device.raw.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty()).vk("vkResetCommandPool")?;
            let begin = vk::CommandBufferBeginInfo::default();
            device.raw.begin_command_buffer(self.cmd, &begin).vk("vkBeginCommandBuffer")?;
        }
        Ok(self.cmd)
    }

    /// End the recording.
    pub fn end(&self, device: &Device) -> Result<()> {
        // SAFETY: the buffer is recording.
        unsafe { device.raw.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")
    }

    /// Destroy the pool (and with it the command buffer).
    ///
    /// # Safety
    /// The command buffer must not be pending.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: caller guarantees it is not pending.
        unsafe {
            super::live::destroyed(self.pool);
            device.raw.destroy_command_pool(self.pool, None)
        };
    }
}

/// Submit one command buffer with synchronization2, signalling `fence`.
pub fn submit(
    device: &Device,
    cmd: vk::CommandBuffer,
    wait: &[vk::SemaphoreSubmitInfo],
    signal: &[vk::SemaphoreSubmitInfo],
    fence: vk::Fence,
) -> Result<()> {
    let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
    let submit = vk::SubmitInfo2::default()
        .wait_semaphore_infos(wait)
        .command_buffer_infos(&cmds)
        .signal_semaphore_infos(signal);
    // SAFETY: cmd is executable; semaphores and fence belong to this device.
    unsafe { device.raw.queue_submit2(device.queue, &[submit], fence) }.vk("vkQueueSubmit2")
}

/// Record with `record`, submit, and wait for completion. For start-up work only.
pub fn submit_and_wait<T>(
    device: &Device,
    name: &str,
    record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
) -> Result<T> {
    // Destroyed on the way out: after the fence was waited, or the device is idle.
    let recorder = Guard::new(device, CommandRecorder::new(device, name)?);
    let fence = Guard::new(device, sync::fence(device, false, &format!("{name} fence"))?);
    let result = (|| {
        let cmd = recorder.begin(device)?;
        let value = record(cmd)?;
        recorder.end(device)?;
        submit(device, cmd, &[], &[], *fence)?;
        sync::wait_fence(device, *fence)?;
        Ok(value)
    })();
    if result.is_err() {
        // A failed submission or wait leaves nothing we can trust pending; make sure of it.
        let _ = device.wait_idle();
    }
    // The guards destroy the fence and the recorder here.
    result
}
