//! Command-buffer labels: every pass is a named region in validation messages and captures.

use ash::vk;

use crate::vk::device::Device;

/// Open a labelled region; pair with [`end_label`].
pub fn begin_label(device: &Device, cmd: vk::CommandBuffer, name: &str, color: [f32; 4]) {
    let Ok(name) = std::ffi::CString::new(name) else {
        return;
    };
    let Some(debug_utils) = &device.debug_utils else {
        return;
    };
    let label = vk::DebugUtilsLabelEXT::default().label_name(&name).color(color);
    // SAFETY: cmd is recording.
    unsafe { debug_utils.cmd_begin_debug_utils_label(cmd, &label) };
}

/// Close the innermost labelled region.
pub fn end_label(device: &Device, cmd: vk::CommandBuffer) {
    if let Some(debug_utils) = &device.debug_utils {
        // SAFETY: cmd is recording, with an open label.
        unsafe { debug_utils.cmd_end_debug_utils_label(cmd) };
    }
}
