//! Physical devices: what the loader offers (`list_devices`, `meadow devices`), how each is
//! described (`DeviceInfo`), and which one a `DeviceSelector` picks for the logical device.

use std::ffi::CStr;

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::instance::Instance;

/// How to pick the physical device.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// Best by type: discrete > integrated > virtual > CPU.
    #[default]
    Best,
    /// Index in `meadow devices`.
    Index(usize),
    /// Case-insensitive substring of the device name.
    Name(String),
}

impl DeviceSelector {
    /// `INDEX` or `NAME-SUBSTRING`, as given to `--device`.
    pub fn parse(text: &str) -> Self {
        match text.parse::<usize>() {
            Ok(index) => DeviceSelector::Index(index),
            Err(_) => DeviceSelector::Name(text.to_lowercase()),
        }
    }
}

/// What one physical device is, as listed by `meadow devices`.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Position in the instance's enumeration.
    pub index: usize,
    /// `deviceName`.
    pub name: String,
    /// Discrete, integrated, CPU …
    pub kind: vk::PhysicalDeviceType,
    /// Supported Vulkan API version, `major.minor.patch`.
    pub api_version: String,
    /// Driver version decoded with the vendor's convention.
    pub driver_version: String,
    /// `driverName` (e.g. `llvmpipe`).
    pub driver_name: String,
    /// `driverInfo` (e.g. `Mesa 22.3.6 (LLVM 15.0.6)`).
    pub driver_info: String,
    /// Whether meadow can run on it (API 1.3, a graphics+compute queue).
    pub usable: bool,
    /// A portability-subset implementation (MoltenVK): `VK_KHR_portability_subset` is enabled on it.
    pub portability_subset: bool,
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} ({}, Vulkan {}, driver {} {} [{}]){}{}",
            self.index,
            self.name,
            kind_name(self.kind),
            self.api_version,
            self.driver_name,
            self.driver_version,
            self.driver_info,
            if self.usable { "" } else { " - unusable: needs Vulkan 1.3 and a graphics queue" },
            if self.portability_subset { " - portability subset (VK_KHR_portability_subset enabled)" } else { "" }
        )
    }
}

fn kind_name(kind: vk::PhysicalDeviceType) -> &'static str {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU",
        _ => "other",
    }
}

/// Preference order of device types (lower is better).
fn kind_rank(kind: vk::PhysicalDeviceType) -> u32 {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// Decode `driverVersion` with the vendor's packing (NVIDIA uses 10.8.8.6 bits; the rest follow
/// `VK_MAKE_API_VERSION`).
pub fn decode_driver_version(vendor_id: u32, version: u32) -> String {
    match vendor_id {
        0x10de => format!(
            "{}.{}.{}.{}",
            (version >> 22) & 0x3ff,
            (version >> 14) & 0xff,
            (version >> 6) & 0xff,
            version & 0x3f
        ),
        _ => format!(
            "{}.{}.{}",
            vk::api_version_major(version),
            vk::api_version_minor(version),
            vk::api_version_patch(version)
        ),
    }
}

fn c_chars(raw: &[std::ffi::c_char]) -> String {
    // SAFETY: Vulkan strings in property structs are NUL-terminated within their arrays.
    let bytes: &[u8] = unsafe { std::slice::from_raw_parts(raw.as_ptr().cast(), raw.len()) };
    CStr::from_bytes_until_nul(bytes).map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

pub(crate) struct Candidate {
    /// What `meadow devices` prints.
    pub(crate) info: DeviceInfo,
    /// The handle.
    pub(crate) raw: vk::PhysicalDevice,
    /// Its graphics+compute family, if it has one.
    pub(crate) queue_family: Option<u32>,
    /// Whether it offers `VK_KHR_swapchain` (what a window needs; `MEADOW_HIDE=swapchain` hides it).
    pub(crate) swapchain: bool,
    /// With a window: whether its queue family can present to the window's surface
    /// (`MEADOW_HIDE=present` says none can); `None` without a window.
    pub(crate) presents: Option<bool>,
    /// Whether it is a portability-subset implementation (MoltenVK): `VK_KHR_portability_subset`
    /// must then be enabled.
    pub(crate) portability_subset: bool,
}

/// Whether `raw` offers the device extension `name`.
fn has_extension(instance: &Instance, raw: vk::PhysicalDevice, name: &CStr) -> bool {
    // SAFETY: raw comes from this instance.
    let available = unsafe { instance.raw.enumerate_device_extension_properties(raw) }.unwrap_or_default();
    available.iter().any(|e| e.extension_name_as_c_str() == Ok(name))
}

pub(crate) fn enumerate(instance: &Instance) -> Result<Vec<Candidate>> {
    // SAFETY: valid instance.
    let devices = unsafe { instance.raw.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    Ok(devices
        .into_iter()
        .enumerate()
        .map(|(index, raw)| {
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
            // SAFETY: raw comes from this instance; the chain points to locals.
            unsafe { instance.raw.get_physical_device_properties2(raw, &mut props2) };
            let props = props2.properties;
            // SAFETY: raw comes from this instance.
            let families = unsafe { instance.raw.get_physical_device_queue_family_properties(raw) };
            let queue_family = families
                .iter()
                .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE))
                .map(|i| i as u32);
            let info = DeviceInfo {
                index,
                name: c_chars(&props.device_name),
                kind: props.device_type,
                api_version: format!(
                    "{}.{}.{}",
                    vk::api_version_major(props.api_version),
                    vk::api_version_minor(props.api_version),
                    vk::api_version_patch(props.api_version)
                ),
                driver_version: decode_driver_version(props.vendor_id, props.driver_version),
                driver_name: c_chars(&driver.driver_name),
                driver_info: c_chars(&driver.driver_info),
                usable: props.api_version >= vk::API_VERSION_1_3 && queue_family.is_some(),
                portability_subset: has_extension(instance, raw, ash::khr::portability_subset::NAME),
            };
            let hidden = super::capabilities::hidden().is_ok_and(|h| h.swapchain);
            let swapchain = !hidden && has_extension(instance, raw, ash::khr::swapchain::NAME);
            let portability_subset = info.portability_subset;
            Candidate { info, raw, queue_family, swapchain, presents: None, portability_subset }
        })
        .collect())
}

/// List every physical device the loader sees.
pub fn list_devices(instance: &Instance) -> Result<Vec<DeviceInfo>> {
    Ok(enumerate(instance)?.into_iter().map(|c| c.info).collect())
}

/// The candidate `selector` names, if meadow can run on it (and present to a window, when
/// `swapchain`: the best device is chosen among those that offer `VK_KHR_swapchain` and whose
/// queue can present to the window's surface, `Candidate::presents`).
pub(crate) fn select<'a>(
    candidates: &'a [Candidate],
    selector: &DeviceSelector,
    swapchain: bool,
) -> Result<&'a Candidate> {
    if candidates.is_empty() {
        return Err(Error::Environment(
            "no Vulkan device found: install mesa-vulkan-drivers for the lavapipe CPU device".into(),
        ));
    }
    let listing = || candidates.iter().map(|c| c.info.to_string()).collect::<Vec<_>>().join("; ");
    let chosen = match selector {
        DeviceSelector::Best => candidates
            .iter()
            .filter(|c| c.info.usable && (!swapchain || (c.swapchain && c.presents != Some(false))))
            .min_by_key(|c| (kind_rank(c.info.kind), c.info.index))
            .ok_or_else(|| {
                let offers = |c: &&Candidate| c.info.usable && c.swapchain;
                match (swapchain, candidates.iter().any(|c| c.info.usable), candidates.iter().any(|c| offers(&c))) {
                    (true, true, true) => Error::Environment(format!(
                        "no Vulkan 1.3 device with VK_KHR_swapchain can present to this window: {}",
                        listing()
                    )),
                    (true, true, false) => Error::Environment(format!(
                        "no Vulkan 1.3 device offers VK_KHR_swapchain for a window: {}",
                        listing()
                    )),
                    _ => Error::Environment(format!("no device supports Vulkan 1.3: {}", listing())),
                }
            })?,
        DeviceSelector::Index(index) => candidates
            .get(*index)
            .ok_or_else(|| Error::bad_input(format!("--device {index}: no such device (have {})", listing())))?,
        DeviceSelector::Name(name) => {
            candidates.iter().find(|c| c.info.name.to_lowercase().contains(name.as_str())).ok_or_else(|| {
                Error::bad_input(format!(
                    "--device {}: no device name contains it (have {})",
                    crate::error::quoted(name),
                    listing()
                ))
            })?
        }
    };
    if !chosen.info.usable {
        return Err(Error::bad_input(format!(
            "--device: {} cannot run meadow (needs Vulkan 1.3 and a graphics+compute queue)",
            chosen.info.name
        )));
    }
    if swapchain && !chosen.swapchain {
        return Err(Error::Environment(format!(
            "{} lacks VK_KHR_swapchain: it cannot present to a window",
            chosen.info.name
        )));
    }
    if swapchain && chosen.presents == Some(false) {
        return Err(Error::Environment(format!(
            "{}: its graphics+compute queue cannot present to this window's surface",
            chosen.info.name
        )));
    }
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn driver_versions_decode_per_vendor() {
        // NVIDIA 535.154.5.0 packed as 10.8.8.6 bits.
        let nv = (535 << 22) | (154 << 14) | (5 << 6);
        assert_eq!(decode_driver_version(0x10de, nv), "535.154.5.0");
        assert_eq!(decode_driver_version(0x10005, vk::make_api_version(0, 22, 3, 6)), "22.3.6");
    }

    #[test]
    fn selector_parses_index_or_name() {
        assert_eq!(DeviceSelector::parse("1"), DeviceSelector::Index(1));
        assert_eq!(DeviceSelector::parse("LLVMpipe"), DeviceSelector::Name("llvmpipe".into()));
    }
}
