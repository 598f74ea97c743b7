//! Images: an `ImageDesc` value describes a 2-D image, or a 3-D one (`ImageDesc::volume`: a
//! simulation's grid, a wind field, read and written as a storage image and sampled), `Image`
//! owns the handle, its default view and its gpu-allocator allocation. Both have one layer and
//! one mip level unless made with mips (`ImageDesc::with_mips`: an atlas), whose default view
//! spans them all and whose levels `vk::tracker` tracks apart (`Resource::Image`'s `base_mip`);
//! a single-mip image is tracked as a whole (`Resource::color`).

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkContext};
use crate::vk::device::Device;
use crate::vk::guard::Guard;

/// Description of a 2-D or 3-D image.
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
    /// `Some(depth)`: a 3-D image (`VK_IMAGE_TYPE_3D`, a 3-D view) `depth` texels deep; `None`: 2-D.
    pub volume: Option<u32>,
    /// Mip levels (1 unless `with_mips`).
    pub mips: u32,
}

impl<'a> ImageDesc<'a> {
    /// A colour image of `format`.
    pub fn color(name: &'a str, format: vk::Format, extent: vk::Extent2D, usage: vk::ImageUsageFlags) -> Self {
        let (aspect, samples) = (vk::ImageAspectFlags::COLOR, vk::SampleCountFlags::TYPE_1);
        Self { format, extent, usage, aspect, name, samples, volume: None, mips: 1 }
    }

    /// A 3-D colour image of `format` (e.g. a grid of velocities, `R16G16B16A16_SFLOAT`, written
    /// as a storage image and sampled). Its first use transitions it from UNDEFINED: import it as
    /// `[Access::Nothing]` (or upload it, `UploadBatch::image`).
    pub fn volume(name: &'a str, format: vk::Format, extent: vk::Extent3D, usage: vk::ImageUsageFlags) -> Self {
        let flat = vk::Extent2D { width: extent.width, height: extent.height };
        Self { volume: Some(extent.depth), ..Self::color(name, format, flat, usage) }
    }

    /// The same 2-D image with `mips` mip levels (each half the one before, at least a texel).
    pub fn with_mips(self, mips: u32) -> Self {
        Self { mips, ..self }
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
            volume: None,
            mips: 1,
        }
    }

    /// Width, height and depth (1 for a 2-D image).
    pub fn extent_3d(&self) -> vk::Extent3D {
        vk::Extent3D { width: self.extent.width, height: self.extent.height, depth: self.volume.unwrap_or(1) }
    }

    /// The image type and the type of its default view.
    fn types(&self) -> (vk::ImageType, vk::ImageViewType) {
        match self.volume {
            Some(_) => (vk::ImageType::TYPE_3D, vk::ImageViewType::TYPE_3D),
            None => (vk::ImageType::TYPE_2D, vk::ImageViewType::TYPE_2D),
        }
    }

    /// Subresource range of the whole image.
    pub fn range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange { aspect_mask: self.aspect, level_count: self.mips, ..COLOR_RANGE }
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

/// Record the copy of a whole single-mip colour image, 2-D or 3-D (a transfer source now), into
/// `buffer`, tightly packed (slice after slice). The barriers around it are the caller's
/// (`render::graph` derives them).
pub fn record_copy_to_buffer(
    device: &Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent3D,
    buffer: vk::Buffer,
) {
    let region = vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(extent);
    // SAFETY: cmd is recording outside a rendering instance; the image is in TRANSFER_SRC_OPTIMAL
    // and the buffer holds width × height × depth texels.
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

/// A device-local 2-D or 3-D image with one mip level and its view.
pub struct Image {
    /// The image handle.
    pub raw: vk::Image,
    /// Its view over the whole image.
    pub view: vk::ImageView,
    /// Format, extent, usage it was created with.
    pub format: vk::Format,
    /// Width and height.
    pub extent: vk::Extent2D,
    /// Depth: 1 for a 2-D image.
    pub depth: u32,
    /// Range of the whole image (for barriers).
    pub range: vk::ImageSubresourceRange,
    allocation: Allocation,
}

impl Image {
    /// Create the image, allocate its memory, create the view, name all three. On failure nothing
    /// is left. A 3-D image the device cannot make (format, usage, extent) is refused first.
    pub fn new(device: &Device, desc: &ImageDesc) -> Result<Self> {
        let (image_type, view_type) = desc.types();
        if desc.volume.is_some() {
            check_volume(device, desc)?;
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(image_type)
            .format(desc.format)
            .extent(desc.extent_3d())
            .mip_levels(desc.mips)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info.
        let raw = super::live::created(unsafe { device.raw.create_image(&info, None) }.vk("vkCreateImage")?);
        let raw = Guard::new(device, raw);
        // SAFETY: raw was just created from this device.
        let requirements = unsafe { device.raw.get_image_memory_requirements(*raw) };
        let allocation = device.allocate(&AllocationCreateDesc {
            name: desc.name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = Guard::new(device, allocation.map_err(|source| Error::allocation(desc.name, source))?);
        // SAFETY: the allocation satisfies the image's requirements.
        unsafe { device.raw.bind_image_memory(*raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindImageMemory")?;
        let range = desc.range();
        let view_info = vk::ImageViewCreateInfo::default()
            .image(*raw)
            .view_type(view_type)
            .format(desc.format)
            .subresource_range(range);
        // SAFETY: the image is bound to memory.
        let view = unsafe { device.raw.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        let view = super::live::created(view);
        let raw = raw.take();
        device.set_name(raw, desc.name);
        device.set_name(view, &format!("{} view", desc.name));
        let (format, extent, depth, allocation) = (desc.format, desc.extent, desc.extent_3d().depth, allocation.take());
        Ok(Self { raw, view, format, extent, depth, range, allocation })
    }

    /// Width, height and depth (1 for a 2-D image).
    pub fn extent_3d(&self) -> vk::Extent3D {
        vk::Extent3D { width: self.extent.width, height: self.extent.height, depth: self.depth }
    }

    /// A 2-D view of mip `level` alone (a storage image's level, an attachment's), named after
    /// the image; the caller destroys it before the image.
    pub fn mip_view(&self, device: &Device, level: u32, name: &str) -> Result<vk::ImageView> {
        let range = vk::ImageSubresourceRange { base_mip_level: level, level_count: 1, ..self.range };
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(self.format)
            .subresource_range(range);
        // SAFETY: the image is bound to memory and has the level.
        let view = unsafe { device.raw.create_image_view(&info, None) }.vk("vkCreateImageView")?;
        let view = super::live::created(view);
        device.set_name(view, &format!("{name} level {level}"));
        Ok(view)
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

/// Refuse a 3-D image the device cannot make: its format and usage unsupported for 3-D images,
/// or its extent past the format's `maxExtent` (`vkGetPhysicalDeviceImageFormatProperties`).
fn check_volume(device: &Device, desc: &ImageDesc) -> Result<()> {
    let (format, usage, extent) = (desc.format, desc.usage, desc.extent_3d());
    // SAFETY: valid physical device and enums.
    let properties = unsafe {
        device.instance.raw.get_physical_device_image_format_properties(
            device.physical,
            format,
            vk::ImageType::TYPE_3D,
            vk::ImageTiling::OPTIMAL,
            usage,
            vk::ImageCreateFlags::empty(),
        )
    };
    let max = match properties {
        Ok(properties) => properties.max_extent,
        Err(vk::Result::ERROR_FORMAT_NOT_SUPPORTED) => {
            return Err(Error::Environment(format!(
                "{}: the device cannot make a 3-D {format:?} image with usage {usage:?}",
                desc.name
            )))
        }
        Err(e) => return Err(Error::vulkan("vkGetPhysicalDeviceImageFormatProperties", e)),
    };
    if extent.width > max.width || extent.height > max.height || extent.depth > max.depth {
        return Err(Error::bad_input(format!(
            "{}: a 3-D {format:?} image of {}x{}x{} is over the device's maxExtent of {}x{}x{} for it",
            desc.name, extent.width, extent.height, extent.depth, max.width, max.height, max.depth
        )));
    }
    Ok(())
}
