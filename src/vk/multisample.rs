//! Multisampling: which sample counts a device supports for the attachments meadow renders into.

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::Device;

/// One attachment: its format and how it is used (attachment, and sampled when a pass reads it).
#[derive(Clone, Copy, Debug)]
pub struct AttachmentUse {
    /// Texel format.
    pub format: vk::Format,
    /// Usage flags of the image.
    pub usage: vk::ImageUsageFlags,
}

/// The `SampleCountFlags` bit for `samples` (1, 2, 4 … 64), if it is one.
pub fn flag(samples: u32) -> Option<vk::SampleCountFlags> {
    (samples.is_power_of_two() && samples <= 64).then(|| vk::SampleCountFlags::from_raw(samples))
}

/// The sample counts every one of `attachments` supports on `device`, ascending (1 always):
/// the framebuffer limits for colour and depth, the sampled-image limits for those read by a
/// shader, and the format's own image properties for its usage.
pub fn supported_counts(device: &Device, attachments: &[AttachmentUse]) -> Vec<u32> {
    let limits = device.limits();
    let mut mask = vk::SampleCountFlags::from_raw(0x7f);
    for attachment in attachments {
        let depth = is_depth(attachment.format);
        mask &= if depth { limits.framebuffer_depth_sample_counts } else { limits.framebuffer_color_sample_counts };
        if attachment.usage.contains(vk::ImageUsageFlags::SAMPLED) {
            mask &=
                if depth { limits.sampled_image_depth_sample_counts } else { limits.sampled_image_color_sample_counts };
        }
        let properties = format_properties(device, attachment);
        mask &= properties.map_or(vk::SampleCountFlags::TYPE_1, |p| p.sample_counts);
        if device.format_features(attachment.format).is_empty() {
            mask = vk::SampleCountFlags::TYPE_1;
        }
    }
    (0..7).map(|bit| 1u32 << bit).filter(|&n| n == 1 || mask.contains(vk::SampleCountFlags::from_raw(n))).collect()
}

/// Refuse an image of `attachment` (texels of `texel_bytes`) at `extent` with `samples` samples
/// that the device cannot create: past the format's `maxExtent` or `maxResourceSize`
/// (`vkGetPhysicalDeviceImageFormatProperties`). `what` names the request in the message.
pub fn check_extent(
    device: &Device,
    attachment: &AttachmentUse,
    texel_bytes: u64,
    (extent, samples): (vk::Extent2D, u32),
    what: &str,
) -> Result<()> {
    let properties = format_properties(device, attachment).vk("vkGetPhysicalDeviceImageFormatProperties")?;
    let max = properties.max_extent;
    if extent.width > max.width || extent.height > max.height {
        return Err(Error::bad_input(format!(
            "{what}: a {:?} image of {}x{} is over the device's maxExtent of {}x{} for it",
            attachment.format, extent.width, extent.height, max.width, max.height
        )));
    }
    let bytes = u64::from(extent.width) * u64::from(extent.height) * u64::from(samples) * texel_bytes;
    if bytes > properties.max_resource_size {
        return Err(Error::bad_input(format!(
            "{what}: a {samples}-sample {:?} image of {}x{} takes {}, over the device's maxResourceSize of {} for it",
            attachment.format,
            extent.width,
            extent.height,
            super::device::format_bytes(bytes),
            super::device::format_bytes(properties.max_resource_size)
        )));
    }
    Ok(())
}

/// The format's image properties for `attachment`'s usage as an optimally tiled 2-D image.
fn format_properties(device: &Device, attachment: &AttachmentUse) -> ash::prelude::VkResult<vk::ImageFormatProperties> {
    // SAFETY: valid physical device and enums.
    unsafe {
        device.instance.raw.get_physical_device_image_format_properties(
            device.physical,
            attachment.format,
            vk::ImageType::TYPE_2D,
            vk::ImageTiling::OPTIMAL,
            attachment.usage,
            vk::ImageCreateFlags::empty(),
        )
    }
}

fn is_depth(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D16_UNORM
            | vk::Format::D32_SFLOAT
            | vk::Format::X8_D24_UNORM_PACK32
            | vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
    )
}
