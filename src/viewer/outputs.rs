//! What a viewer session writes, checked before any work: the exit screenshot, the script's
//! screenshots (each a writable path, no two the same file) and the overlay's capture directory;
//! and the buffer a screenshot is read back through.

use ash::vk;

use super::{script, Viewer, ViewerOptions};
use crate::app;
use crate::error::{Error, Result};

/// Check every output `options` names; the first bad one is bad input.
pub(super) fn check(options: &ViewerOptions) -> Result<()> {
    let script_shots = options.script.iter().flat_map(|s| &s.actions).filter_map(|(_, action)| match action {
        script::Action::Screenshot(path) => Some((std::path::Path::new(path.as_str()), "script screenshot")),
        _ => None,
    });
    let shots: Vec<_> = options.screenshot.iter().map(|p| (p.as_path(), "--screenshot")).chain(script_shots).collect();
    for &(path, flag) in &shots {
        app::output::check_output(path, flag)?;
    }
    // Two screenshots to one file: the second would replace the first.
    app::output::check_distinct(shots.iter().map(|&(path, flag)| (flag, path.to_path_buf())))?;
    if let Some(dir) = options.capture_dir.as_ref().filter(|d| !d.is_dir()) {
        return Err(Error::bad_input(format!("--capture-dir {}: not a directory", dir.display())));
    }
    Ok(())
}

impl Viewer {
    /// The host-visible buffer a requested screenshot is copied into. Allocated before the image
    /// is acquired: a failure must not strand an acquired image.
    pub(super) fn screenshot_buffer(&self) -> Result<Option<crate::vk::Buffer>> {
        Ok(match (&self.screenshot, &self.surface) {
            (Some(path), Some(surface)) if !surface.swapchain.screenshots => {
                return Err(Error::Environment(format!(
                    "screenshot {}: this surface's images cannot be copied (no TRANSFER_SRC usage)",
                    path.display()
                )));
            }
            (Some(_), Some(surface)) => {
                let e = surface.swapchain.extent;
                Some(crate::vk::Buffer::new(
                    &self.device,
                    &crate::vk::BufferDesc::readback(
                        "screenshot",
                        4 * u64::from(e.width) * u64::from(e.height),
                        vk::BufferUsageFlags::TRANSFER_DST,
                    ),
                )?)
            }
            _ => None,
        })
    }
}
