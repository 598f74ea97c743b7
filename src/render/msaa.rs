//! Multisample anti-aliasing (`--msaa N`): the scene passes draw into a multisampled colour and
//! depth pair in linear light ([`MSAA_COLOR_FORMAT`], the shaders do not encode), the depth
//! pyramid reads the farthest of each pixel's depth samples, and the resolve pass
//! (`passes/resolve.rs`) averages each pixel's samples in linear space and encodes the result
//! into the frame's target. Averaging the sRGB-encoded values a UNORM target holds would darken
//! every edge; the hardware resolve of an sRGB target is not required to linearise either.

use ash::vk;

use crate::error::{Error, Result};
use crate::render::target::TargetView;
use crate::vk::multisample::{self, AttachmentUse};
use crate::vk::{Access, Device, Guard, Image, ImageDesc};

/// Colour of the multisampled scene: linear, 16-bit float (colour attachment and sampled, both
/// required of this format by the specification), values above 1 clamped by the resolve.
pub const MSAA_COLOR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// Samples per pixel and how the alpha-tested outline uses them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Msaa {
    /// Samples per pixel; 1 is no multisampling.
    pub samples: u32,
    /// The outline's alpha becomes sample coverage (alpha to coverage) instead of an alpha test.
    pub alpha_to_coverage: bool,
}

impl Default for Msaa {
    fn default() -> Self {
        Self { samples: 1, alpha_to_coverage: true }
    }
}

impl Msaa {
    /// Whether the scene is multisampled.
    pub fn enabled(&self) -> bool {
        self.samples > 1
    }

    /// The sample-count flag of the scene's attachments.
    pub fn flag(&self) -> vk::SampleCountFlags {
        multisample::flag(self.samples).unwrap_or(vk::SampleCountFlags::TYPE_1)
    }
}

/// The multisampled attachments as meadow uses them: colour drawn and resolved by a shader,
/// depth drawn and read by the depth pyramid.
fn attachments(device: &Device) -> [AttachmentUse; 2] {
    let sampled = vk::ImageUsageFlags::SAMPLED;
    [
        AttachmentUse { format: MSAA_COLOR_FORMAT, usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | sampled },
        AttachmentUse { format: device.depth_format, usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | sampled },
    ]
}

/// Bytes per sample of the multisampled colour ([`MSAA_COLOR_FORMAT`]) and depth (at most 4).
const SAMPLE_BYTES: [u64; 2] = [8, 4];

/// Bytes of device memory the multisampled colour and depth of a frame of `extent` take (none
/// without multisampling): counted by every budget check with the frame's other targets.
pub fn target_bytes(extent: vk::Extent2D, msaa: &Msaa) -> u64 {
    match msaa.enabled() {
        true => linear_bytes(extent) * u64::from(msaa.samples),
        false => 0,
    }
}

/// Bytes of device memory a single-sampled linear colour and depth pair of `extent` takes
/// (`--fade blend`'s, checked when it is made).
pub fn linear_bytes(extent: vk::Extent2D) -> u64 {
    u64::from(extent.width) * u64::from(extent.height) * SAMPLE_BYTES.iter().sum::<u64>()
}

/// Refuse a frame of `extent` whose multisampled images the device cannot create (past a
/// format's `maxExtent` or `maxResourceSize`); `what` names the request (`--size 8192x8192`).
pub fn check_target(device: &Device, extent: vk::Extent2D, msaa: &Msaa, what: &str) -> Result<()> {
    if !msaa.enabled() {
        return Ok(());
    }
    for (attachment, bytes) in attachments(device).iter().zip(SAMPLE_BYTES) {
        multisample::check_extent(
            device,
            attachment,
            bytes,
            (extent, msaa.samples),
            &format!("{what} --msaa {}", msaa.samples),
        )?;
    }
    Ok(())
}

/// The sample counts `--msaa` accepts on `device`, ascending.
pub fn supported_counts(device: &Device) -> Vec<u32> {
    multisample::supported_counts(device, &attachments(device))
}

/// Refuse a sample count the device does not support for the formats in use (bad input), and
/// alpha to coverage where the samples are not at the standard locations its shader tests
/// (`blade.frag`, variant `coverage`).
pub fn check(device: &Device, msaa: &Msaa) -> Result<()> {
    let supported = supported_counts(device);
    if supported.contains(&msaa.samples) {
        if msaa.enabled() && msaa.alpha_to_coverage && device.limits().standard_sample_locations == vk::FALSE {
            return Err(Error::BadInput(format!(
                "--msaa {}: {} does not place samples at the standard locations alpha to coverage tests; add --no-alpha-to-coverage",
                msaa.samples, device.info.name
            )));
        }
        return Ok(());
    }
    let list: Vec<String> = supported.iter().map(u32::to_string).collect();
    Err(Error::BadInput(format!(
        "--msaa {} is not supported by {} for the formats in use ({MSAA_COLOR_FORMAT:?} colour, {:?} depth, both sampled); supported: {}",
        msaa.samples,
        device.info.name,
        device.depth_format,
        list.join(", ")
    )))
}

/// The multisampled colour and depth the scene passes draw into.
pub struct MultisampleTarget {
    color: Image,
    depth: Image,
    samples: vk::SampleCountFlags,
}

impl MultisampleTarget {
    /// Create both images at `extent` with `samples` samples.
    pub fn new(device: &Device, extent: vk::Extent2D, samples: vk::SampleCountFlags) -> Result<Self> {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let color_desc = ImageDesc::color("multisampled colour", MSAA_COLOR_FORMAT, extent, usage);
        let color = Guard::new(device, Image::new(device, &color_desc.multisampled(samples))?);
        let depth_desc = ImageDesc::depth("multisampled depth", device.depth_format, extent).multisampled(samples);
        let depth = Image::new(device, &depth_desc)?;
        Ok(Self { color: color.take(), depth, samples })
    }

    /// Whether the images fit a frame of `extent` with `samples` samples.
    pub fn fits(&self, extent: vk::Extent2D, samples: vk::SampleCountFlags) -> bool {
        self.color.extent == extent && self.samples == samples
    }

    /// The scene passes' view of it. Its images are tracked by the graph from their creation
    /// (imported once, as `Nothing`), so the previous accesses here are never used.
    pub fn view(&self) -> TargetView {
        TargetView::of(&self.color, &self.depth, (Access::Nothing, Access::Nothing))
    }

    /// Free both images.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.depth.destroy(device);
            self.color.destroy(device);
        }
    }
}
