//! The viewer's surface: the window, its swapchain and depth image, the target of a frame into
//! an acquired image, and the screenshot written from a frame's readback.

use ash::vk;
use winit::window::Window;

use crate::app;
use crate::error::Result;
use crate::render::target::TargetView;
use crate::render::Renderer;
use crate::vk::swapchain::Swapchain;
use crate::vk::{Access, Buffer, Image};

/// The window's swapchain and depth image.
pub(super) struct Surface {
    pub(super) swapchain: Swapchain,
    pub(super) depth: Option<Image>,
    /// Whether a submitted frame has used `depth` since it was created.
    pub(super) depth_used: bool,
    pub(super) window: Window,
}

impl Surface {
    /// The target of a frame into swapchain image `index` (just acquired) and the depth image
    /// (discarded until a frame has been submitted with it).
    pub(super) fn target_view(&self, index: u32) -> TargetView {
        let depth = self.depth.as_ref().expect("depth exists with area");
        TargetView {
            color: self.swapchain.images[index as usize],
            color_view: self.swapchain.views[index as usize],
            depth: depth.raw,
            depth_view: depth.view,
            extent: self.swapchain.extent,
            color_previous: Access::Acquired,
            depth_previous: if self.depth_used { Access::DepthAttachmentReadWrite } else { Access::Nothing },
        }
    }

    /// Write the screenshot the last frame copied into `buffer` (after waiting for it).
    pub(super) fn write_screenshot(
        &self,
        renderer: &mut Renderer,
        buffer: &Buffer,
        path: &std::path::Path,
    ) -> Result<()> {
        renderer.wait_all_frames()?;
        let extent = self.swapchain.extent;
        let bgra = self.swapchain.format == vk::Format::B8G8R8A8_UNORM;
        let rgba: Vec<u8> = if bgra {
            buffer.mapped().chunks_exact(4).flat_map(|p| [p[2], p[1], p[0], p[3]]).collect()
        } else {
            buffer.mapped().to_vec()
        };
        app::write_png(path, (extent.width, extent.height), &rgba)?;
        println!("screenshot: {} ({}x{})", path.display(), extent.width, extent.height);
        Ok(())
    }
}
