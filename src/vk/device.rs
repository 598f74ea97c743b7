//! The logical device (the physical one is chosen by `vk::physical`): one graphics+compute queue, the
//! synchronization2 / dynamic-rendering features, and the gpu-allocator instance all memory
//! comes from.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{Error, Result, VkContext};
use crate::vk::instance::Instance;
pub use crate::vk::physical::{decode_driver_version, list_devices, DeviceInfo, DeviceSelector};
use crate::vk::physical::{enumerate, select};

/// Memory budget meadow allows itself regardless of what the device reports (issue 2, item 6).
pub const MEMORY_BUDGET_BYTES: u64 = 2 << 30;

/// What the logical device is created with.
#[derive(Clone, Debug, Default)]
pub struct DeviceDesc {
    /// Which physical device.
    pub selector: DeviceSelector,
    /// Enable `VK_KHR_swapchain` (the viewer).
    pub swapchain: bool,
    /// The window's surface: only a device whose queue can present to it is chosen.
    pub surface: Option<vk::SurfaceKHR>,
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
    /// `shaderDrawParameters` (Vulkan 1.1; `gl_DrawID`) is enabled.
    pub draw_parameters: bool,
    /// `VK_EXT_calibrated_timestamps` with the device and CLOCK_MONOTONIC domains, if enabled.
    pub calibrated_timestamps: Option<ash::ext::calibrated_timestamps::Device>,
    /// The logical device and its function table.
    pub raw: ash::Device,
    /// Debug-utils device functions (object names, labels), when the instance has the extension.
    pub debug_utils: Option<ash::ext::debug_utils::Device>,
    /// The one graphics+compute queue.
    pub queue: vk::Queue,
    /// Its family index.
    pub queue_family: u32,
    /// `timestampValidBits` of that family.
    pub timestamp_valid_bits: u32,
    /// `subgroupSize` (Vulkan 1.1): how many invocations the device runs in lockstep.
    pub subgroup_size: u32,
    /// The backend profile the shaders and the scene's bindings are built for (`MEADOW_PROFILE`).
    pub profile: super::profile::Profile,
    /// The depth format of every depth attachment (reversed Z, also sampled by the depth
    /// pyramid): the first of [`DEPTH_FORMATS`] the device can attach and sample.
    pub depth_format: vk::Format,
    allocator: ManuallyDrop<Mutex<Allocator>>,
}

/// Depth formats in order of preference: D32_SFLOAT (not required of a device), then the
/// 24-bit and the 16-bit UNORM formats (D16_UNORM attachment and sampling are required).
pub const DEPTH_FORMATS: [vk::Format; 3] =
    [vk::Format::D32_SFLOAT, vk::Format::X8_D24_UNORM_PACK32, vk::Format::D16_UNORM];

/// What meadow does with a depth format: attach it and sample it (the depth pyramid).
const DEPTH_FEATURES: vk::FormatFeatureFlags = vk::FormatFeatureFlags::from_raw(
    vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT.as_raw() | vk::FormatFeatureFlags::SAMPLED_IMAGE.as_raw(),
);

/// What `format` supports on `physical` with optimal tiling (nothing when `MEADOW_HIDE` hides it).
fn format_features(instance: &Instance, physical: vk::PhysicalDevice, format: vk::Format) -> vk::FormatFeatureFlags {
    if super::capabilities::hidden().is_ok_and(|h| h.hides(format)) {
        return vk::FormatFeatureFlags::empty();
    }
    // SAFETY: physical comes from this instance; any format may be queried.
    unsafe { instance.raw.get_physical_device_format_properties(physical, format) }.optimal_tiling_features
}

/// The first of [`DEPTH_FORMATS`] `physical` can attach and sample, or a refusal naming `name`.
fn depth_format(instance: &Instance, physical: vk::PhysicalDevice, name: &str) -> Result<vk::Format> {
    DEPTH_FORMATS
        .into_iter()
        .find(|&f| format_features(instance, physical, f).contains(DEPTH_FEATURES))
        .ok_or_else(|| Error::Environment(format!("{name} can attach and sample none of {DEPTH_FORMATS:?}")))
}

/// The features meadow enables on `physical`.
struct EnabledFeatures {
    /// Optional core features, enabled when supported.
    core: vk::PhysicalDeviceFeatures,
    /// `drawIndirectCount` (Vulkan 1.2).
    draw_indirect_count: bool,
    /// `shaderDrawParameters` (Vulkan 1.1).
    draw_parameters: bool,
}

/// Query what `physical` supports: synchronization2 and dynamic rendering are required, the
/// optional core features and `drawIndirectCount` are enabled when present.
fn enabled_features(instance: &Instance, physical: vk::PhysicalDevice, name: &str) -> Result<EnabledFeatures> {
    // SAFETY: physical comes from this instance.
    let supported = unsafe { instance.raw.get_physical_device_features(physical) };
    let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut supported12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut supported11 = vk::PhysicalDeviceVulkan11Features::default();
    let mut supported2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut supported13)
        .push_next(&mut supported12)
        .push_next(&mut supported11);
    // SAFETY: as above; the chain points to locals.
    unsafe { instance.raw.get_physical_device_features2(physical, &mut supported2) };
    if supported13.synchronization2 == vk::FALSE || supported13.dynamic_rendering == vk::FALSE {
        return Err(Error::Environment(format!("{name} lacks synchronization2 or dynamic rendering")));
    }
    // The depth-only layouts (DEPTH_ATTACHMENT_OPTIMAL, DEPTH_READ_ONLY_OPTIMAL) need it; Vulkan
    // 1.2 requires every device to support it, so a device without it is refused.
    let hidden = super::capabilities::hidden()?;
    if supported12.separate_depth_stencil_layouts == vk::FALSE || hidden.separate_depth_stencil_layouts {
        return Err(Error::Environment(format!(
            "{name} lacks separateDepthStencilLayouts (the depth-only image layouts meadow uses)"
        )));
    }
    let core = vk::PhysicalDeviceFeatures {
        pipeline_statistics_query: supported.pipeline_statistics_query,
        multi_draw_indirect: match hidden.multi_draw_indirect {
            true => vk::FALSE,
            false => supported.multi_draw_indirect,
        },
        draw_indirect_first_instance: supported.draw_indirect_first_instance,
        fill_mode_non_solid: supported.fill_mode_non_solid,
        ..Default::default()
    };
    let draw_indirect_count = supported12.draw_indirect_count == vk::TRUE && !hidden.draw_indirect_count;
    let draw_parameters = supported11.shader_draw_parameters == vk::TRUE && !hidden.draw_parameters;
    Ok(EnabledFeatures { core, draw_indirect_count, draw_parameters })
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
    let mut features12 = vk::PhysicalDeviceVulkan12Features::default()
        .draw_indirect_count(features.draw_indirect_count)
        .separate_depth_stencil_layouts(true);
    let mut features11 = vk::PhysicalDeviceVulkan11Features::default().shader_draw_parameters(features.draw_parameters);
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .features(features.core)
        .push_next(&mut features11)
        .push_next(&mut features12)
        .push_next(&mut features13);
    let priorities = [1.0];
    let queue_infos =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
    let create_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .enabled_extension_names(extensions)
        .push_next(&mut features2);
    // lavapipe crashes inside vkCreateDevice under a tight `ulimit -v`: said first.
    // SAFETY: physical comes from this instance.
    let properties = unsafe { instance.raw.get_physical_device_properties(physical) };
    let name = properties.device_name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    super::address_space::check_device(properties.device_type, &name)?;
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

/// The largest picture side (`maxImageDimension2D`, `maxFramebufferWidth` and `Height`, the
/// smallest of them) of the device `selector` picks for a window, known before the window exists:
/// the window's size is checked against it first (a window past what the device renders is of
/// no use, and past what the platform takes it cannot even be made). Which devices can present
/// to the window is not known yet; `Device::new` chooses among those, and the viewer checks the
/// chosen one's limits again.
pub fn window_side_limit(instance: &Instance, selector: &DeviceSelector) -> Result<u32> {
    let candidates = enumerate(instance)?;
    let chosen = select(&candidates, selector, true)?;
    // SAFETY: the handle comes from this instance.
    let limits = unsafe { instance.raw.get_physical_device_properties(chosen.raw) }.limits;
    Ok(limits.max_image_dimension2_d.min(limits.max_framebuffer_width).min(limits.max_framebuffer_height))
}

impl Device {
    /// Select a physical device and create the logical device on it.
    pub fn new(instance: Arc<Instance>, desc: &DeviceDesc) -> Result<Arc<Self>> {
        let mut candidates = enumerate(&instance)?;
        if let Some(surface) = desc.surface {
            presenting(&instance, &mut candidates, surface)?;
        }
        let chosen = select(&candidates, &desc.selector, desc.swapchain)?;
        let (physical, profile) = (chosen.raw, super::profile::Profile::choose(&chosen.info.driver_name)?);
        let queue_family = chosen.queue_family.expect("usable devices have a queue family");

        // SAFETY: physical comes from this instance.
        let (mut properties, memory, families) = unsafe {
            (
                instance.raw.get_physical_device_properties(physical),
                instance.raw.get_physical_device_memory_properties(physical),
                instance.raw.get_physical_device_queue_family_properties(physical),
            )
        };
        let features = enabled_features(&instance, physical, &chosen.info.name)?;
        super::capabilities::hidden()?.limit(&mut properties.limits);
        let depth_format = depth_format(&instance, physical, &chosen.info.name)?;
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut properties2 = vk::PhysicalDeviceProperties2::default().push_next(&mut subgroup);
        // SAFETY: physical comes from this Vulkan 1.1+ instance; the chain is valid.
        unsafe { instance.raw.get_physical_device_properties2(physical, &mut properties2) };
        let mut extensions = Vec::new();
        if desc.swapchain {
            extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        if chosen.portability_subset {
            // Required on a portability-subset implementation (MoltenVK); meadow uses none of
            // the features it may leave out.
            extensions.push(ash::khr::portability_subset::NAME.as_ptr());
        }
        let calibrated = supports_calibrated_timestamps(&instance, physical);
        if calibrated {
            extensions.push(ash::ext::calibrated_timestamps::NAME.as_ptr());
        }
        let raw = create_logical(&instance, physical, queue_family, &features, &extensions)?;
        // SAFETY: the family was requested with one queue.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        let debug_utils =
            instance.debug_utils.as_ref().map(|_| ash::ext::debug_utils::Device::new(&instance.raw, &raw));
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
            draw_parameters: features.draw_parameters,
            calibrated_timestamps,
            raw,
            debug_utils,
            queue,
            queue_family,
            timestamp_valid_bits: match super::capabilities::hidden()? {
                hidden if hidden.timestamps => 0,
                hidden => families[queue_family as usize].timestamp_valid_bits.min(hidden.timestamp_bits.unwrap_or(64)),
            },
            subgroup_size: subgroup.subgroup_size,
            profile,
            depth_format,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
        };
        device.set_name(device.queue, "main queue");
        Ok(Arc::new(device))
    }

    /// Whether the queue can write timestamps (`timestampValidBits` > 0): GPU times are
    /// measured, or "unavailable".
    pub fn has_timestamps(&self) -> bool {
        self.timestamp_valid_bits > 0
    }

    /// Core device limits (as `MEADOW_HIDE` leaves them).
    pub fn limits(&self) -> &vk::PhysicalDeviceLimits {
        &self.properties.limits
    }

    /// What `format` supports with optimal tiling (nothing when `MEADOW_HIDE` hides it).
    pub fn format_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        format_features(&self.instance, self.physical, format)
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
        // A software device's memory is mapped into this process: under `ulimit -v` too.
        match self.info.kind == vk::PhysicalDeviceType::CPU {
            true => super::address_space::check_headroom(bytes, what),
            false => Ok(()),
        }
    }

    /// Lock the allocator.
    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A panic while holding the lock leaves the allocator consistent for freeing.
        self.allocator.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Allocate memory for `desc` from the allocator (`MEADOW_INJECT_ALLOC_FAILURE`: `vk::fault`).
    pub fn allocate(
        &self,
        desc: &gpu_allocator::vulkan::AllocationCreateDesc,
    ) -> std::result::Result<gpu_allocator::vulkan::Allocation, gpu_allocator::AllocationError> {
        if super::fault::fails(super::fault::Fault::Allocation) {
            return Err(gpu_allocator::AllocationError::OutOfMemory);
        }
        self.allocator().allocate(desc)
    }

    /// Return `allocation` to the allocator. Its error (a double free, a foreign allocation: a
    /// bug) cannot be returned from the destructors that call this, so it is logged and counted
    /// ([`free_errors`]): the command then exits 1 (`cli::run`). `MEADOW_INJECT_FREE_FAILURE`
    /// (`vk::fault`) reports one.
    pub fn free(&self, allocation: gpu_allocator::vulkan::Allocation, name: &str) {
        let mut result = self.allocator().free(allocation);
        if super::fault::fails(super::fault::Fault::Free) {
            result = Err(gpu_allocator::AllocationError::Internal("injected failure".into()));
        }
        if let Err(e) = result {
            FREE_ERRORS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            log::error!("freeing the memory of `{name}`: {e}");
        }
    }

    /// Give a Vulkan object a debug name (shown by validation messages and captures).
    pub fn set_name<T: vk::Handle>(&self, handle: T, name: &str) {
        let (Some(debug_utils), Ok(name)) = (&self.debug_utils, std::ffi::CString::new(name)) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
        // SAFETY: the handle belongs to this device; naming failure is harmless, so it is ignored.
        let _ = unsafe { debug_utils.set_debug_utils_object_name(&info) };
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

/// Mark which candidates' queue can present to `surface` (`MEADOW_HIDE=present`: none).
fn presenting(
    instance: &Instance,
    candidates: &mut [super::physical::Candidate],
    surface: vk::SurfaceKHR,
) -> Result<()> {
    let hidden = super::capabilities::hidden()?.present;
    let loader = ash::khr::surface::Instance::new(&instance.entry, &instance.raw);
    for c in candidates.iter_mut() {
        // SAFETY: the device and the surface come from this instance.
        let supported = |family| unsafe { loader.get_physical_device_surface_support(c.raw, family, surface) };
        c.presents = Some(!hidden && c.queue_family.is_some_and(|family| supported(family).unwrap_or(false)));
    }
    Ok(())
}

static FREE_ERRORS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// How many frees the allocator refused in this process (`Device::free`).
pub fn free_errors() -> u64 {
    FREE_ERRORS.load(std::sync::atomic::Ordering::Relaxed)
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
    fn bytes_format() {
        assert_eq!(format_bytes(512), "512 B");
        assert_eq!(format_bytes(32 << 20), "32.0 MiB");
        assert_eq!(format_bytes(2 << 30), "2.0 GiB");
    }
}
