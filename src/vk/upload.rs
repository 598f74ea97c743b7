//! Staging uploads: data is written to host-visible staging buffers, copied into device-local
//! buffers and images in one command buffer, and each destination is handed to its first reader
//! with a barrier declared as accesses. One submission and one wait per batch, at start-up.

use ash::vk;

use crate::error::Result;
use crate::vk::buffer::{Buffer, BufferDesc};
use crate::vk::commands;
use crate::vk::device::Device;
use crate::vk::guard::Guard;
use crate::vk::image::{Image, ImageDesc};
use crate::vk::sync::{self, Access};

enum Copy {
    Buffer {
        staging: Buffer,
        dst: vk::Buffer,
        next: &'static [Access],
    },
    Image {
        staging: Buffer,
        dst: vk::Image,
        extent: vk::Extent3D,
        range: vk::ImageSubresourceRange,
        next: &'static [Access],
    },
}

/// A set of uploads recorded and submitted together. Staging buffers of a batch dropped without
/// `submit` (an error path) are freed on drop.
pub struct UploadBatch<'d> {
    device: &'d Device,
    copies: Vec<Copy>,
}

impl<'d> UploadBatch<'d> {
    /// An empty batch.
    pub fn new(device: &'d Device) -> Self {
        Self { device, copies: Vec::new() }
    }

    /// The device the batch uploads to.
    pub fn device(&self) -> &'d Device {
        self.device
    }

    /// Create a device-local buffer filled with `data` once the batch is submitted; `next` is how
    /// it is read afterwards.
    pub fn buffer<T: bytemuck::Pod>(
        &mut self,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
        next: &'static [Access],
    ) -> Result<Buffer> {
        let device = self.device;
        let size = std::mem::size_of_val(data) as vk::DeviceSize;
        let staging_name = format!("{name} staging");
        let staging = Buffer::with_data(
            device,
            &BufferDesc::upload(&staging_name, size, vk::BufferUsageFlags::TRANSFER_SRC),
            data,
        )?;
        // Never used by the GPU until the batch is submitted.
        let staging = Guard::new(device, staging);
        let dst = Buffer::new(device, &BufferDesc::gpu_only(name, size, usage | vk::BufferUsageFlags::TRANSFER_DST))?;
        self.copies.push(Copy::Buffer { staging: staging.take(), dst: dst.raw, next });
        Ok(dst)
    }

    /// Create a device-local image, 2-D or 3-D, holding `texels` (tightly packed rows, slice after
    /// slice) once submitted.
    pub fn image(&mut self, desc: &ImageDesc, texels: &[u8], next: &'static [Access]) -> Result<Image> {
        let device = self.device;
        let staging_name = format!("{} staging", desc.name);
        let staging = Buffer::with_data(
            device,
            &BufferDesc::upload(&staging_name, texels.len() as vk::DeviceSize, vk::BufferUsageFlags::TRANSFER_SRC),
            texels,
        )?;
        let mut desc = *desc;
        desc.usage |= vk::ImageUsageFlags::TRANSFER_DST;
        let staging = Guard::new(device, staging);
        let image = Image::new(device, &desc)?;
        self.copies.push(Copy::Image {
            staging: staging.take(),
            dst: image.raw,
            extent: image.extent_3d(),
            range: image.range,
            next,
        });
        Ok(image)
    }

    /// Record every copy with its barriers, submit, wait, and free the staging buffers.
    pub fn submit(mut self) -> Result<()> {
        let device = self.device;
        let copies = std::mem::take(&mut self.copies);
        let result = commands::submit_and_wait(device, "upload", |cmd| {
            // Images: UNDEFINED → transfer destination before their copies.
            let to_transfer: Vec<_> = copies
                .iter()
                .filter_map(|copy| match copy {
                    Copy::Image { dst, range, .. } => {
                        Some(sync::image_barrier(*dst, *range, &[Access::Nothing], &[Access::TransferWrite]))
                    }
                    Copy::Buffer { .. } => None,
                })
                .collect();
            sync::cmd_barriers(device, cmd, &[], &to_transfer);
            let mut buffer_barriers = Vec::new();
            let mut image_barriers = Vec::new();
            for copy in &copies {
                match copy {
                    Copy::Buffer { staging, dst, next } => {
                        let region = vk::BufferCopy { src_offset: 0, dst_offset: 0, size: staging.size };
                        // SAFETY: both buffers are live and large enough.
                        unsafe { device.raw.cmd_copy_buffer(cmd, staging.raw, *dst, &[region]) };
                        buffer_barriers.push(sync::buffer_barrier(*dst, &[Access::TransferWrite], next));
                    }
                    Copy::Image { staging, dst, extent, range, next } => {
                        let region = vk::BufferImageCopy::default()
                            .image_subresource(vk::ImageSubresourceLayers {
                                aspect_mask: range.aspect_mask,
                                mip_level: 0,
                                base_array_layer: 0,
                                layer_count: 1,
                            })
                            .image_extent(*extent);
                        // SAFETY: the image is in TRANSFER_DST_OPTIMAL after the barrier above.
                        unsafe {
                            device.raw.cmd_copy_buffer_to_image(
                                cmd,
                                staging.raw,
                                *dst,
                                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                                &[region],
                            )
                        };
                        image_barriers.push(sync::image_barrier(*dst, *range, &[Access::TransferWrite], next));
                    }
                }
            }
            sync::cmd_barriers(device, cmd, &buffer_barriers, &image_barriers);
            Ok(())
        });
        // SAFETY: submit_and_wait returned, so the copies are complete (or the device idle).
        unsafe { free_staging(device, copies) };
        result
    }
}

impl Drop for UploadBatch<'_> {
    fn drop(&mut self) {
        // SAFETY: copies still here were never submitted.
        unsafe { free_staging(self.device, std::mem::take(&mut self.copies)) };
    }
}

/// # Safety
/// The GPU must be done with the staging buffers.
unsafe fn free_staging(device: &Device, copies: Vec<Copy>) {
    for copy in copies {
        let staging = match copy {
            Copy::Buffer { staging, .. } | Copy::Image { staging, .. } => staging,
        };
        // SAFETY: per the function's contract.
        unsafe { staging.destroy(device) };
    }
}
