//! Multisampling: which sample counts a device supports for the attachments meadow renders into.

use ash::vk;

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
        // SAFETY: valid physical device and enums.
        let properties = unsafe {
            device.instance.raw.get_physical_device_image_format_properties(
                device.physical,
                attachment.format,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                attachment.usage,
                vk::ImageCreateFlags::empty(),
            )
        };
        mask &= properties.map_or(vk::SampleCountFlags::TYPE_1, |p| p.sample_counts);
        if device.format_features(attachment.format).is_empty() {
            mask = vk::SampleCountFlags::TYPE_1;
        }
    }
    (0..7).map(|bit| 1u32 << bit).filter(|&n| n == 1 || mask.contains(vk::SampleCountFlags::from_raw(n))).collect()
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
