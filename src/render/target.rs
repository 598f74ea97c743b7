//! Render targets. The renderer draws into a [`TargetView`]; `OffscreenTarget` provides one for
//! headless rendering and reads the picture back, a swapchain will provide the same view.

use ash::vk;

use crate::error::Result;
use crate::vk::{Access, Buffer, BufferDesc, Device, Guard, Image, ImageDesc};

/// Colour format of offscreen targets: UNORM, the shaders encode sRGB themselves.
pub const OFFSCREEN_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// What a frame renders into, and how the colour image is used before and after.
#[derive(Clone, Copy, Debug)]
pub struct TargetView {
    /// Colour image.
    pub color: vk::Image,
    /// Its view.
    pub color_view: vk::ImageView,
    /// Depth image.
    pub depth: vk::Image,
    /// Its view.
    pub depth_view: vk::ImageView,
    /// Size of both.
    pub extent: vk::Extent2D,
    /// How the colour image was last accessed (`Nothing` discards it).
    pub color_previous: Access,
    /// How the depth image was last accessed.
    pub depth_previous: Access,
}

impl TargetView {
    /// The view of a `color` and `depth` image pair, last accessed as given.
    pub fn of(color: &Image, depth: &Image, previous: (Access, Access)) -> Self {
        TargetView {
            color: color.raw,
            color_view: color.view,
            depth: depth.raw,
            depth_view: depth.view,
            extent: color.extent,
            color_previous: previous.0,
            depth_previous: previous.1,
        }
    }
}

/// Bytes of device memory an offscreen target of `extent` needs (colour, depth, readback).
pub fn offscreen_bytes(extent: vk::Extent2D) -> u64 {
    3 * 4 * u64::from(extent.width) * u64::from(extent.height)
}

/// A colour + depth target with a host-visible readback buffer.
pub struct OffscreenTarget {
    /// RGBA8 UNORM colour.
    pub color: Image,
    /// D32 depth.
    pub depth: Image,
    /// Tightly packed RGBA8 copy of the last frame.
    pub readback: Buffer,
    /// Last access recorded to the depth image (Nothing before the first frame).
    depth_last: Access,
    /// Last access recorded to the colour image.
    color_last: Access,
}

impl OffscreenTarget {
    /// Create the images and the readback buffer.
    pub fn new(device: &Device, extent: vk::Extent2D) -> Result<Self> {
        let color = Image::new(
            device,
            &ImageDesc::color(
                "offscreen colour",
                OFFSCREEN_FORMAT,
                extent,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            ),
        )?;
        let color = Guard::new(device, color);
        let depth =
            Guard::new(device, Image::new(device, &ImageDesc::depth("offscreen depth", device.depth_format, extent))?);
        let bytes = 4 * u64::from(extent.width) * u64::from(extent.height);
        let readback = Buffer::new(
            device,
            &BufferDesc::readback("offscreen readback", bytes, vk::BufferUsageFlags::TRANSFER_DST),
        )?;
        let (color, depth) = (color.take(), depth.take());
        Ok(Self { color, depth, readback, depth_last: Access::Nothing, color_last: Access::Nothing })
    }

    /// The view the renderer draws into.
    pub fn view(&self) -> TargetView {
        TargetView::of(&self.color, &self.depth, (self.color_last, self.depth_last))
    }

    /// Note that a frame was recorded into the target with a readback: it leaves colour as a
    /// copy source and, if the frame drew into it (`depth_used`), depth as an attachment (the
    /// next frame's first barriers start there).
    pub fn rendered(&mut self, depth_used: bool) {
        if depth_used {
            self.depth_last = Access::DepthAttachmentReadWrite;
        }
        self.color_last = Access::TransferRead;
    }

    /// The RGBA8 pixels of the last completed frame (call after its fence).
    pub fn pixels(&self) -> &[u8] {
        self.readback.mapped()
    }

    /// Free everything.
    ///
    /// # Safety
    /// No pending work may use the target.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.readback.destroy(device);
            self.depth.destroy(device);
            self.color.destroy(device);
        }
    }
}

impl crate::vk::Destroy for OffscreenTarget {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { OffscreenTarget::destroy(self, device) };
    }
}
