//! Command-buffer labels: every pass is a named region in validation messages and captures.

use ash::vk;

use crate::vk::device::Device;

/// Open a labelled region; pair with [`end_label`].
/// Without the debug-utils extension it does nothing; a name of up to 63 bytes is terminated on
/// the stack (a frame's labels allocate nothing), a longer one in a `CString`.
pub fn begin_label(device: &Device, cmd: vk::CommandBuffer, name: &str, color: [f32; 4]) {
    let Some(debug_utils) = &device.debug_utils else {
        return;
    };
    let mut short = [0u8; 64];
    let long;
    let name = match name.len() < short.len() {
        true => {
            short[..name.len()].copy_from_slice(name.as_bytes());
            std::ffi::CStr::from_bytes_until_nul(&short).unwrap_or_default()
        }
        false => {
            let Ok(owned) = std::ffi::CString::new(name) else { return };
            long = owned;
            long.as_c_str()
        }
    };
    let label = vk::DebugUtilsLabelEXT::default().label_name(name).color(color);
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
