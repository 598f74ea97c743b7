//! Physical-device selection and the logical device: one graphics+compute queue, the
//! synchronization2 / dynamic-rendering features, and the gpu-allocator instance all memory
//! comes from.

use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{Error, Result, VkContext};
use crate::vk::instance::Instance;

/// Memory budget meadow allows itself regardless of what the device reports (issue 2, item 6).
pub const MEMORY_BUDGET_BYTES: u64 = 2 << 30;

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
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} ({}, Vulkan {}, driver {} {} [{}]){}",
            self.index,
            self.name,
            kind_name(self.kind),
            self.api_version,
            self.driver_name,
            self.driver_version,
            self.driver_info,
            if self.usable { "" } else { " - unusable: needs Vulkan 1.3 and a graphics queue" }
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

struct Candidate {
    info: DeviceInfo,
    raw: vk::PhysicalDevice,
    queue_family: Option<u32>,
}

fn enumerate(instance: &Instance) -> Result<Vec<Candidate>> {
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
            };
            Candidate { info, raw, queue_family }
        })
        .collect())
}

/// List every physical device the loader sees.
pub fn list_devices(instance: &Instance) -> Result<Vec<DeviceInfo>> {
    Ok(enumerate(instance)?.into_iter().map(|c| c.info).collect())
}

/// What the logical device is created with.
#[derive(Clone, Debug, Default)]
pub struct DeviceDesc {
    /// Which physical device.
    pub selector: DeviceSelector,
    /// Enable `VK_KHR_swapchain` (the viewer).
    pub swapchain: bool,
}

/// The logical device and everything created with it: queue, allocator, debug-utils functions.
///
/// Shared behind an `Arc` by every owner of GPU objects; the last owner to drop destroys the
/// allocator and the device, then releases the instance.
pub struct Device {
    /// The instance this device was created from (kept alive by this reference).
    pub instance: Arc<Instance>,
    /// The physical device.
    pub physical: vk::PhysicalDevice,
    /// What `meadow devices` prints about it.
    pub info: DeviceInfo,
    /// Core properties, including `limits`.
    pub properties: vk::PhysicalDeviceProperties,
    /// Memory heaps and types.
    pub memory: vk::PhysicalDeviceMemoryProperties,
    /// Enabled core features (pipeline statistics, multi-draw-indirect, first instance in
    /// indirect draws, non-solid fill, when supported).
    pub features: vk::PhysicalDeviceFeatures,
    /// `drawIndirectCount` (Vulkan 1.2) enabled: `vkCmdDrawIndirectCount` may be used.
    pub draw_indirect_count: bool,
    /// `VK_EXT_calibrated_timestamps` with the device and CLOCK_MONOTONIC domains, if enabled.
    pub calibrated_timestamps: Option<ash::ext::calibrated_timestamps::Device>,
    /// The logical device and its function table.
    pub raw: ash::Device,
    /// Debug-utils device functions (object names, labels).
    pub debug_utils: ash::ext::debug_utils::Device,
    /// The one graphics+compute queue.
    pub queue: vk::Queue,
    /// Its family index.
    pub queue_family: u32,
    /// `timestampValidBits` of that family.
    pub timestamp_valid_bits: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
}

/// The candidate `selector` names, if meadow can run on it.
fn select<'a>(candidates: &'a [Candidate], selector: &DeviceSelector) -> Result<&'a Candidate> {
    if candidates.is_empty() {
        return Err(Error::Environment(
            "no Vulkan device found: install mesa-vulkan-drivers for the lavapipe CPU device".into(),
        ));
    }
    let listing = || candidates.iter().map(|c| c.info.to_string()).collect::<Vec<_>>().join("; ");
    let chosen = match selector {
        DeviceSelector::Best => candidates
            .iter()
            .filter(|c| c.info.usable)
            .min_by_key(|c| (kind_rank(c.info.kind), c.info.index))
            .ok_or_else(|| Error::Environment(format!("no device supports Vulkan 1.3: {}", listing())))?,
        DeviceSelector::Index(index) => candidates
            .get(*index)
            .ok_or_else(|| Error::bad_input(format!("--device {index}: no such device (have {})", listing())))?,
        DeviceSelector::Name(name) => {
            candidates.iter().find(|c| c.info.name.to_lowercase().contains(name.as_str())).ok_or_else(|| {
                Error::bad_input(format!("--device {name}: no device name contains it (have {})", listing()))
            })?
        }
    };
    if !chosen.info.usable {
        return Err(Error::bad_input(format!(
            "--device: {} cannot run meadow (needs Vulkan 1.3 and a graphics+compute queue)",
            chosen.info.name
        )));
    }
    Ok(chosen)
}

/// The features meadow enables on `physical`.
struct EnabledFeatures {
    /// Optional core features, enabled when supported.
    core: vk::PhysicalDeviceFeatures,
    /// `drawIndirectCount` (Vulkan 1.2).
    draw_indirect_count: bool,
}

/// Query what `physical` supports: synchronization2 and dynamic rendering are required, the
/// optional core features and `drawIndirectCount` are enabled when present.
fn enabled_features(instance: &Instance, physical: vk::PhysicalDevice, name: &str) -> Result<EnabledFeatures> {
    // SAFETY: physical comes from this instance.
    let supported = unsafe { instance.raw.get_physical_device_features(physical) };
    let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut supported12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut supported2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13).push_next(&mut supported12);
    // SAFETY: as above; the chain points to locals.
    unsafe { instance.raw.get_physical_device_features2(physical, &mut supported2) };
    if supported13.synchronization2 == vk::FALSE || supported13.dynamic_rendering == vk::FALSE {
        return Err(Error::Environment(format!("{name} lacks synchronization2 or dynamic rendering")));
    }
    let core = vk::PhysicalDeviceFeatures {
        pipeline_statistics_query: supported.pipeline_statistics_query,
        multi_draw_indirect: supported.multi_draw_indirect,
        draw_indirect_first_instance: supported.draw_indirect_first_instance,
        fill_mode_non_solid: supported.fill_mode_non_solid,
        ..Default::default()
    };
    Ok(EnabledFeatures { core, draw_indirect_count: supported12.draw_indirect_count == vk::TRUE })
}

/// Whether `physical` has VK_EXT_calibrated_timestamps and can correlate its timestamps with
/// CLOCK_MONOTONIC (what `std::time::Instant` reads on Linux): `meadow timing` puts CPU and GPU
/// spans on one timeline with it.
fn supports_calibrated_timestamps(instance: &Instance, physical: vk::PhysicalDevice) -> bool {
    // SAFETY: physical comes from this instance.
    let available = unsafe { instance.raw.enumerate_device_extension_properties(physical) }.unwrap_or_default();
    let has = available.iter().any(|e| e.extension_name_as_c_str() == Ok(ash::ext::calibrated_timestamps::NAME));
    let domains = if has {
        let ext = ash::ext::calibrated_timestamps::Instance::new(&instance.entry, &instance.raw);
        // SAFETY: the device supports the extension.
        unsafe { ext.get_physical_device_calibrateable_time_domains(physical) }.unwrap_or_default()
    } else {
        Vec::new()
    };
    has && domains.contains(&vk::TimeDomainEXT::DEVICE) && domains.contains(&vk::TimeDomainEXT::CLOCK_MONOTONIC)
}

/// Create the logical device with one queue of `queue_family`, `features` (plus
/// synchronization2 and dynamic rendering) and `extensions`.
fn create_logical(
    instance: &Instance,
    physical: vk::PhysicalDevice,
    queue_family: u32,
    features: &EnabledFeatures,
    extensions: &[*const std::ffi::c_char],
) -> Result<ash::Device> {
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true).dynamic_rendering(true);
    let mut features12 =
        vk::PhysicalDeviceVulkan12Features::default().draw_indirect_count(features.draw_indirect_count);
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .features(features.core)
        .push_next(&mut features12)
        .push_next(&mut features13);
    let priorities = [1.0];
    let queue_infos =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
    let create_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .enabled_extension_names(extensions)
        .push_next(&mut features2);
    // SAFETY: every pointer in create_info refers to locals (or to `extensions`, static
    // extension names) alive for this call.
    unsafe { instance.raw.create_device(physical, &create_info, None) }.vk("vkCreateDevice")
}

/// The allocator every GPU allocation comes from; it logs leaks when dropped.
fn create_allocator(
    instance: &Instance,
    raw: &ash::Device,
    physical: vk::PhysicalDevice,
) -> gpu_allocator::Result<Allocator> {
    let mut debug_settings = gpu_allocator::AllocatorDebugSettings::default();
    debug_settings.log_leaks_on_shutdown = true;
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.raw.clone(),
        device: raw.clone(),
        physical_device: physical,
        debug_settings,
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
}

impl Device {
    /// Select a physical device and create the logical device on it.
    pub fn new(instance: Arc<Instance>, desc: &DeviceDesc) -> Result<Arc<Self>> {
        let candidates = enumerate(&instance)?;
        let chosen = select(&candidates, &desc.selector)?;
        let physical = chosen.raw;
        let queue_family = chosen.queue_family.expect("usable devices have a queue family");

        // SAFETY: physical comes from this instance.
        let (properties, memory, families) = unsafe {
            (
                instance.raw.get_physical_device_properties(physical),
                instance.raw.get_physical_device_memory_properties(physical),
                instance.raw.get_physical_device_queue_family_properties(physical),
            )
        };
        let features = enabled_features(&instance, physical, &chosen.info.name)?;
        let mut extensions = Vec::new();
        if desc.swapchain {
            extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        let calibrated = supports_calibrated_timestamps(&instance, physical);
        if calibrated {
            extensions.push(ash::ext::calibrated_timestamps::NAME.as_ptr());
        }
        let raw = create_logical(&instance, physical, queue_family, &features, &extensions)?;
        // SAFETY: the family was requested with one queue.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        let debug_utils = ash::ext::debug_utils::Device::new(&instance.raw, &raw);
        let calibrated_timestamps =
            calibrated.then(|| ash::ext::calibrated_timestamps::Device::new(&instance.raw, &raw));

        let allocator = match create_allocator(&instance, &raw, physical) {
            Ok(allocator) => allocator,
            Err(source) => {
                // SAFETY: nothing was created from the device yet.
                unsafe { raw.destroy_device(None) };
                return Err(Error::Allocation { name: "allocator".into(), source });
            }
        };

        let device = Self {
            info: chosen.info.clone(),
            instance,
            physical,
            properties,
            memory,
            features: features.core,
            draw_indirect_count: features.draw_indirect_count,
            calibrated_timestamps,
            raw,
            debug_utils,
            queue,
            queue_family,
            timestamp_valid_bits: families[queue_family as usize].timestamp_valid_bits,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
        };
        device.set_name(device.queue, "main queue");
        Ok(Arc::new(device))
    }

    /// Core device limits.
    pub fn limits(&self) -> &vk::PhysicalDeviceLimits {
        &self.properties.limits
    }

    /// Size of the largest device-local heap.
    pub fn device_local_heap_bytes(&self) -> u64 {
        self.memory.memory_heaps[..self.memory.memory_heap_count as usize]
            .iter()
            .filter(|heap| heap.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|heap| heap.size)
            .max()
            .unwrap_or(0)
    }

    /// Check that `bytes` of new allocations for `what` fit the device-local heap and meadow's
    /// 2 GiB budget (lavapipe has no memory-budget extension, so we check ourselves).
    pub fn check_budget(&self, bytes: u64, what: &str) -> Result<()> {
        let heap = self.device_local_heap_bytes();
        if bytes > heap {
            return Err(Error::bad_input(format!(
                "{what} needs {} but the device-local heap holds {}",
                format_bytes(bytes),
                format_bytes(heap)
            )));
        }
        if bytes > MEMORY_BUDGET_BYTES {
            return Err(Error::bad_input(format!(
                "{what} needs {}, over meadow's memory budget of {}",
                format_bytes(bytes),
                format_bytes(MEMORY_BUDGET_BYTES)
            )));
        }
        Ok(())
    }

    /// Lock the allocator.
    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A panic while holding the lock leaves the allocator consistent for freeing.
        self.allocator.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Give a Vulkan object a debug name (shown by validation messages and captures).
    pub fn set_name<T: vk::Handle>(&self, handle: T, name: &str) {
        let Ok(name) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
        // SAFETY: the handle belongs to this device; naming failure is harmless, so it is ignored.
        let _ = unsafe { self.debug_utils.set_debug_utils_object_name(&info) };
    }

    /// Wait until the device is idle. Only for teardown and rebuilds, never inside a frame.
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: valid device.
        unsafe { self.raw.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: the last Arc is gone, so every object created from this device has been destroyed
        // by its owner; the allocator must release its memory blocks before the device goes.
        unsafe {
            let _ = self.raw.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.raw.destroy_device(None);
        }
    }
}

/// `1.5 GiB`, `32.0 MiB`, `512 B`.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
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

    #[test]
    fn bytes_format() {
        assert_eq!(format_bytes(512), "512 B");
        assert_eq!(format_bytes(32 << 20), "32.0 MiB");
        assert_eq!(format_bytes(2 << 30), "2.0 GiB");
    }
}
