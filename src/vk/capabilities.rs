//! A capability mask for the tests: `MEADOW_HIDE` hides what lavapipe has and other devices may
//! lack, so that every fallback and refusal runs here. A comma-separated list of:
//!
//! - `separateDepthStencilLayouts`: the Vulkan 1.2 feature is reported unsupported;
//! - `timestamps`: the queue family's `timestampValidBits` reads 0;
//! - `timestampValidBits=N` (1..=64): it reads at most N, so the ticks wrap every 2^N (lavapipe
//!   has 64 bits, desktop GPUs often 36 to 64);
//! - `debug_utils`: the loader reads as lacking `VK_EXT_debug_utils`;
//! - `swapchain`: every device reads as lacking `VK_KHR_swapchain`;
//! - `present`: no device's queue reads as able to present to the window's surface;
//! - `portability_enumeration`: the loader reads as lacking `VK_KHR_portability_enumeration`;
//! - `multiDrawIndirect`: the core feature is reported unsupported (and not enabled), and
//!   `maxDrawIndirectCount` reads 1, as the spec requires of a device without it;
//! - `drawIndirectCount`: the Vulkan 1.2 feature is reported unsupported (and not enabled);
//! - `maxPerStageDescriptorStorageBuffers=N`: the limit reads N;
//! - `maxStorageBufferRange=N` (bytes): the limit reads at most N, so that the buffers sized by it
//!   (the cull's visible list with `--eval blade`: pose records, placed levels) hold fewer entries;
//! - `format:NAME` (e.g. `format:R16G16B16A16_UNORM`): the format reports no features.
//!
//! Read once per process. An entry meadow does not know is refused (a typo must not pass as a
//! mask that hides nothing).

use std::sync::OnceLock;

use ash::vk;

use crate::error::{Error, Result};

/// What `MEADOW_HIDE` hides.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Hidden {
    /// `separateDepthStencilLayouts` reads unsupported.
    pub separate_depth_stencil_layouts: bool,
    /// `timestampValidBits` reads 0.
    pub timestamps: bool,
    /// `timestampValidBits` reads at most this.
    pub timestamp_bits: Option<u32>,
    /// `VK_EXT_debug_utils` reads absent.
    pub debug_utils: bool,
    /// `VK_KHR_swapchain` reads absent.
    pub swapchain: bool,
    /// No queue can present to the window's surface.
    pub present: bool,
    /// `VK_KHR_portability_enumeration` reads absent from the loader.
    pub portability_enumeration: bool,
    /// `multiDrawIndirect` reads unsupported and `maxDrawIndirectCount` 1.
    pub multi_draw_indirect: bool,
    /// `drawIndirectCount` reads unsupported.
    pub draw_indirect_count: bool,
    /// `shaderDrawParameters` reads unsupported.
    pub draw_parameters: bool,
    /// `maxPerStageDescriptorStorageBuffers` reads this.
    pub max_storage_buffers: Option<u32>,
    /// `maxStorageBufferRange` reads at most this.
    pub max_storage_range: Option<u32>,
    /// Formats that report no features.
    pub formats: Vec<vk::Format>,
}

/// Formats a mask may name: those meadow queries before use and can do without (the default
/// keyframe texture's, the multisampled scene colour's, the preferred depth formats).
const FORMATS: [(&str, vk::Format); 4] = [
    ("R16G16B16A16_UNORM", vk::Format::R16G16B16A16_UNORM),
    ("R16G16B16A16_SFLOAT", vk::Format::R16G16B16A16_SFLOAT),
    ("D32_SFLOAT", vk::Format::D32_SFLOAT),
    ("X8_D24_UNORM_PACK32", vk::Format::X8_D24_UNORM_PACK32),
];

impl Hidden {
    /// Parse a mask.
    pub fn parse(text: &str) -> Result<Self> {
        let mut hidden = Self::default();
        for entry in text.split(',').map(str::trim).filter(|e| !e.is_empty()) {
            let unknown = || Error::Environment(format!("MEADOW_HIDE: unknown entry '{entry}'"));
            if entry == "separateDepthStencilLayouts" {
                hidden.separate_depth_stencil_layouts = true;
            } else if entry == "timestamps" {
                hidden.timestamps = true;
            } else if entry == "debug_utils" {
                hidden.debug_utils = true;
            } else if entry == "swapchain" {
                hidden.swapchain = true;
            } else if entry == "present" {
                hidden.present = true;
            } else if entry == "portability_enumeration" {
                hidden.portability_enumeration = true;
            } else if entry == "multiDrawIndirect" {
                hidden.multi_draw_indirect = true;
            } else if entry == "drawIndirectCount" {
                hidden.draw_indirect_count = true;
            } else if entry == "shaderDrawParameters" {
                hidden.draw_parameters = true;
            } else if let Some(n) = entry.strip_prefix("timestampValidBits=") {
                let bits = n.parse().ok().filter(|b| (1..=64).contains(b)).ok_or_else(unknown)?;
                hidden.timestamp_bits = Some(bits);
            } else if let Some(n) = entry.strip_prefix("maxPerStageDescriptorStorageBuffers=") {
                hidden.max_storage_buffers = Some(n.parse().map_err(|_| unknown())?);
            } else if let Some(n) = entry.strip_prefix("maxStorageBufferRange=") {
                hidden.max_storage_range = Some(n.parse().ok().filter(|&n| n > 0).ok_or_else(unknown)?);
            } else if let Some(name) = entry.strip_prefix("format:") {
                let (_, format) = FORMATS.iter().find(|(n, _)| *n == name).ok_or_else(unknown)?;
                hidden.formats.push(*format);
            } else {
                return Err(unknown());
            }
        }
        Ok(hidden)
    }

    /// Apply the limit overrides to `limits`: `maxDrawIndirectCount` "must also be 1" when
    /// `multiDrawIndirect` is not supported (VkPhysicalDeviceFeatures).
    pub fn limit(&self, limits: &mut vk::PhysicalDeviceLimits) {
        if let Some(n) = self.max_storage_buffers {
            limits.max_per_stage_descriptor_storage_buffers = n;
        }
        if let Some(n) = self.max_storage_range {
            limits.max_storage_buffer_range = limits.max_storage_buffer_range.min(n);
        }
        if self.multi_draw_indirect {
            limits.max_draw_indirect_count = 1;
        }
    }

    /// Whether `format` is hidden.
    pub fn hides(&self, format: vk::Format) -> bool {
        self.formats.contains(&format)
    }
}

/// The process's mask (`MEADOW_HIDE`; empty when unset).
pub fn hidden() -> Result<&'static Hidden> {
    static HIDDEN: OnceLock<std::result::Result<Hidden, String>> = OnceLock::new();
    let parsed = HIDDEN
        .get_or_init(|| Hidden::parse(&std::env::var("MEADOW_HIDE").unwrap_or_default()).map_err(|e| e.to_string()));
    parsed.as_ref().map_err(|e| Error::Environment(e.clone()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_kind_of_entry_and_refuses_unknown_ones() {
        let h = Hidden::parse(
            "separateDepthStencilLayouts, timestamps, maxPerStageDescriptorStorageBuffers=4,format:R16G16B16A16_SFLOAT",
        )
        .expect("valid");
        assert!(h.separate_depth_stencil_layouts && h.timestamps);
        assert!(!h.multi_draw_indirect && !h.draw_indirect_count);
        assert_eq!(h.max_storage_buffers, Some(4));
        let draws = Hidden::parse("multiDrawIndirect,drawIndirectCount").expect("valid");
        assert!(draws.multi_draw_indirect && draws.draw_indirect_count);
        let mut limits = vk::PhysicalDeviceLimits { max_draw_indirect_count: 1 << 20, ..Default::default() };
        draws.limit(&mut limits);
        assert_eq!(limits.max_draw_indirect_count, 1, "the spec's limit without multiDrawIndirect");
        assert!(h.hides(vk::Format::R16G16B16A16_SFLOAT) && !h.hides(vk::Format::R16G16B16A16_UNORM));
        assert_eq!(Hidden::parse("").expect("empty"), Hidden::default());
        assert_eq!(Hidden::parse("timestampValidBits=36").expect("valid").timestamp_bits, Some(36));
        let range = Hidden::parse("maxStorageBufferRange=1048576").expect("valid");
        let mut limits = vk::PhysicalDeviceLimits { max_storage_buffer_range: 1 << 27, ..Default::default() };
        range.limit(&mut limits);
        assert_eq!(limits.max_storage_buffer_range, 1 << 20, "the hidden range");
        let mut small = vk::PhysicalDeviceLimits { max_storage_buffer_range: 1 << 10, ..Default::default() };
        range.limit(&mut small);
        assert_eq!(small.max_storage_buffer_range, 1 << 10, "a mask only lowers a limit");
        for bad in [
            "timestampz",
            "format:D16_UNORM",
            "maxPerStageDescriptorStorageBuffers=four",
            "multiDrawIndirect=0",
            "timestampValidBits=0",
            "timestampValidBits=65",
            "maxStorageBufferRange=0",
            "maxStorageBufferRange=big",
        ] {
            assert!(Hidden::parse(bad).is_err(), "{bad}");
        }
    }
}
