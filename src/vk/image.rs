//! Images: an `ImageDesc` value describes a 2D image, `Image` owns the handle, its default view
//! and its gpu-allocator allocation.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkContext};
use crate::vk::device::Device;

/// Description of a 2D image.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc<'a> {
    /// Texel format.
    pub format: vk::Format,
    /// Width and height.
    pub extent: vk::Extent2D,
    /// Usage flags.
    pub usage: vk::ImageUsageFlags,
    /// Aspect of the default view.
    pub aspect: vk::ImageAspectFlags,
    /// Name of the image, its view and its allocation.
    pub name: &'a str,
    /// Samples per texel (`TYPE_1` unless multisampled).
    pub samples: vk::SampleCountFlags,
}

impl<'a> ImageDesc<'a> {
    /// A colour image of `format`.
    pub fn color(name: &'a str, format: vk::Format, extent: vk::Extent2D, usage: vk::ImageUsageFlags) -> Self {
        Self { format, extent, usage, aspect: vk::ImageAspectFlags::COLOR, name, samples: vk::SampleCountFlags::TYPE_1 }
    }

    /// The same image with `samples` samples per texel.
    pub fn multisampled(self, samples: vk::SampleCountFlags) -> Self {
        Self { samples, ..self }
    }

    /// A depth attachment of `format`, also sampled (the cull's depth pyramid reads it).
    pub fn depth(name: &'a str, format: vk::Format, extent: vk::Extent2D) -> Self {
        Self {
            format,
            extent,
            usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            aspect: vk::ImageAspectFlags::DEPTH,
            name,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    /// Subresource range of the whole image.
    pub fn range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange { aspect_mask: self.aspect, ..COLOR_RANGE }
    }
}

/// The one mip level and layer of a colour image (also a swapchain image).
pub const COLOR_RANGE: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

/// Record the copy of a whole single-mip colour image (a transfer source now) into `buffer`,
/// tightly packed. The barriers around it are the caller's (`render::graph` derives them).
pub fn record_copy_to_buffer(
    device: &Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    buffer: vk::Buffer,
) {
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 });
    // SAFETY: cmd is recording outside a rendering instance; the image is in TRANSFER_SRC_OPTIMAL
    // and the buffer holds width × height texels.
    unsafe {
        device.raw.cmd_copy_image_to_buffer(cmd, image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, buffer, &[region])
    };
}

/// The one mip level and layer of a depth image.
pub const DEPTH_RANGE: vk::ImageSubresourceRange =
    vk::ImageSubresourceRange { aspect_mask: vk::ImageAspectFlags::DEPTH, ..COLOR_RANGE };

/// A clamped sampler with `filter` for magnification and minification, no mipmaps.
pub fn clamped_sampler(device: &Device, filter: vk::Filter, name: &str) -> Result<vk::Sampler> {
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(filter)
        .min_filter(filter)
        .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
        .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .max_lod(0.0);
    // SAFETY: valid create info.
    let sampler = super::live::created(unsafe { device.raw.create_sampler(&info, None) }.vk("vkCreateSampler")?);
    device.set_name(sampler, name);
    Ok(sampler)
}

/// A device-local 2D image with one mip level and its view.
pub struct Image {
    /// The image handle.
    pub raw: vk::Image,
    /// Its view over the whole image.
    pub view: vk::ImageView,
    /// Format, extent, usage it was created with.
    pub format: vk::Format,
    /// Width and height.
    pub extent: vk::Extent2D,
    /// Range of the whole image (for barriers).
    pub range: vk::ImageSubresourceRange,
    allocation: Allocation,
}

impl Image {
    /// Create the image, allocate its memory, create the view, name all three.
    pub fn new(device: &Device, desc: &ImageDesc) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.extent.width, height: desc.extent.height, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info.
        let raw = super::live::created(unsafe { device.raw.create_image(&info, None) }.vk("vkCreateImage")?);
        // SAFETY: raw was just created from this device.
        let requirements = unsafe { device.raw.get_image_memory_requirements(raw) };
        let allocation = device.allocate(&AllocationCreateDesc {
            name: desc.name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(allocation) => allocation,
            Err(source) => {
                // SAFETY: unused image of this device.
                unsafe {
                    super::live::destroyed(raw);
                    device.raw.destroy_image(raw, None)
                };
                return Err(Error::allocation(desc.name, source));
            }
        };
        // SAFETY: the allocation satisfies the image's requirements.
        let bound = unsafe { device.raw.bind_image_memory(raw, allocation.memory(), allocation.offset()) };
        let range = desc.range();
        let view = bound.vk("vkBindImageMemory").and_then(|()| {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(desc.format)
                .subresource_range(range);
            // SAFETY: the image is bound to memory.
            unsafe { device.raw.create_image_view(&view_info, None) }.vk("vkCreateImageView").map(super::live::created)
        });
        let view = match view {
            Ok(view) => view,
            Err(e) => {
                device.free(allocation, desc.name);
                // SAFETY: unused image of this device.
                unsafe {
                    super::live::destroyed(raw);
                    device.raw.destroy_image(raw, None)
                };
                return Err(e);
            }
        };
        device.set_name(raw, desc.name);
        device.set_name(view, &format!("{} view", desc.name));
        Ok(Self { raw, view, format: desc.format, extent: desc.extent, range, allocation })
    }

    /// Destroy the view, the image, and free the memory.
    ///
    /// # Safety
    /// No pending GPU work may use the image.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: caller guarantees the GPU is done with it.
        unsafe {
            super::live::destroyed(self.view);
            device.raw.destroy_image_view(self.view, None);
            super::live::destroyed(self.raw);
            device.raw.destroy_image(self.raw, None);
        }
        device.free(self.allocation, "an image");
    }
}
