//! The Vulkan instance: loader, optional Khronos validation with synchronization validation, and
//! the debug messenger that counts every warning and error the layers report.

use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Counts the warnings and errors delivered to the debug messenger.
///
/// Shared with the callback through its user-data pointer; it outlives the instance, so messages
/// emitted while the instance is destroyed (leak reports) are counted too.
#[derive(Debug, Default)]
pub struct ValidationCounter {
    messages: AtomicU64,
}

impl ValidationCounter {
    /// Number of warning and error messages received so far.
    pub fn count(&self) -> u64 {
        self.messages.load(Ordering::SeqCst)
    }
}

/// What the instance is created with.
#[derive(Clone, Copy, Debug, Default)]
pub struct InstanceDesc<'a> {
    /// Enable `VK_LAYER_KHRONOS_validation` with synchronization validation; a missing layer is an
    /// error, never a silent skip.
    pub validation: bool,
    /// Extra instance extensions (e.g. the surface extensions of a window).
    pub extensions: &'a [*const std::ffi::c_char],
}

/// Loader entry, instance, and (with validation) the debug messenger.
pub struct Instance {
    /// The loaded Vulkan library.
    pub entry: ash::Entry,
    /// The instance handle and its function table.
    pub raw: ash::Instance,
    /// Debug-utils instance functions (object names, labels, messenger), when the loader has
    /// `VK_EXT_debug_utils` (optional without validation; `--validation` needs it).
    pub debug_utils: Option<ash::ext::debug_utils::Instance>,
    /// Whether portability implementations (MoltenVK) are listed: the loader offers
    /// `VK_KHR_portability_enumeration` (and `MEADOW_HIDE` does not hide it), so it was enabled
    /// with `ENUMERATE_PORTABILITY_KHR`.
    pub portability_enumeration: bool,
    messenger: vk::DebugUtilsMessengerEXT,
    counter: Option<Arc<ValidationCounter>>,
}

/// Whether the loader offers `VK_EXT_debug_utils` (and `MEADOW_HIDE` does not hide it).
fn debug_utils_available(entry: &ash::Entry) -> Result<bool> {
    if super::capabilities::hidden()?.debug_utils {
        return Ok(false);
    }
    has_instance_extension(entry, ash::ext::debug_utils::NAME)
}

/// Whether the loader (or an implicit layer) offers the instance extension `name`.
fn has_instance_extension(entry: &ash::Entry, name: &std::ffi::CStr) -> Result<bool> {
    // SAFETY: plain query on a valid entry.
    let available =
        unsafe { entry.enumerate_instance_extension_properties(None) }.vk("vkEnumerateInstanceExtensionProperties")?;
    Ok(available.iter().any(|e| e.extension_name_as_c_str() == Ok(name)))
}

/// Load the Vulkan loader and check that it supports API 1.3.
fn load_entry() -> Result<ash::Entry> {
    // SAFETY: loading the system Vulkan loader; its symbols are trusted to match the spec.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| {
        Error::Environment(format!(
            "cannot load the Vulkan loader ({e}): install libvulkan1 and a driver such as mesa-vulkan-drivers"
        ))
    })?;
    // SAFETY: plain query on a valid entry.
    let version = unsafe { entry.try_enumerate_instance_version() }
        .vk("vkEnumerateInstanceVersion")?
        .unwrap_or(vk::API_VERSION_1_0);
    if version < vk::API_VERSION_1_3 {
        return Err(Error::Environment(format!(
            "the Vulkan loader supports API {}.{}, meadow needs 1.3",
            vk::api_version_major(version),
            vk::api_version_minor(version)
        )));
    }
    Ok(entry)
}

/// The layers to enable: the Khronos validation layer with `validation` (an error if it is not
/// installed), none otherwise.
fn layers(entry: &ash::Entry, validation: bool) -> Result<Vec<*const std::ffi::c_char>> {
    if !validation {
        return Ok(Vec::new());
    }
    // SAFETY: plain query on a valid entry.
    let available = unsafe { entry.enumerate_instance_layer_properties() }.vk("vkEnumerateInstanceLayerProperties")?;
    if !available.iter().any(|layer| layer.layer_name_as_c_str() == Ok(VALIDATION_LAYER)) {
        return Err(Error::Environment(
            "validation requested but VK_LAYER_KHRONOS_validation is not installed \
             (install the Debian package vulkan-validationlayers)"
                .into(),
        ));
    }
    Ok(vec![VALIDATION_LAYER.as_ptr()])
}

/// A messenger for warnings and errors of every type, counted into `counter` by
/// `on_debug_message` (its user data is `counter`'s address).
fn messenger_info(counter: &Arc<ValidationCounter>) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_debug_message))
        .user_data(Arc::as_ptr(counter) as *mut c_void)
}

impl Instance {
    /// Load Vulkan and create an instance for API 1.3.
    pub fn new(desc: &InstanceDesc) -> Result<Self> {
        Self::create(desc).map_err(|(e, _)| e)
    }

    /// [`Instance::new`], and on failure also the number of messages the loader and layers
    /// reported while trying (with validation): a missing driver's loader messages are counted.
    pub fn create(desc: &InstanceDesc) -> std::result::Result<Self, (Error, Option<u64>)> {
        let counter = desc.validation.then(|| Arc::new(ValidationCounter::default()));
        Self::create_counted(desc, counter.clone()).map_err(|e| (e, counter.map(|c| c.count())))
    }

    fn create_counted(desc: &InstanceDesc, counter: Option<Arc<ValidationCounter>>) -> Result<Self> {
        let entry = load_entry()?;
        let layers = layers(&entry, desc.validation)?;

        let mut extensions = desc.extensions.to_vec();
        let has_debug_utils = debug_utils_available(&entry)?;
        if has_debug_utils {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        } else if desc.validation {
            return Err(Error::Environment(
                "--validation counts messages through VK_EXT_debug_utils, which the Vulkan loader lacks".into(),
            ));
        }

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"meadow")
            .application_version(vk::make_api_version(0, 0, 1, 0))
            .engine_name(c"meadow")
            .api_version(vk::API_VERSION_1_3);

        let mut messenger_info = counter.as_ref().map(messenger_info);
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);

        // Portability implementations (MoltenVK) are listed only when asked for.
        let portability_enumeration = !super::capabilities::hidden()?.portability_enumeration
            && has_instance_extension(&entry, ash::khr::portability_enumeration::NAME)?;
        let flags = if portability_enumeration {
            extensions.push(ash::khr::portability_enumeration::NAME.as_ptr());
            vk::InstanceCreateFlags::ENUMERATE_PORTABILITY_KHR
        } else {
            vk::InstanceCreateFlags::empty()
        };
        let mut create_info = vk::InstanceCreateInfo::default()
            .flags(flags)
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if let Some(messenger_info) = messenger_info.as_mut() {
            // Chained into the create info, the messenger also reports on vkCreate/DestroyInstance.
            create_info = create_info.push_next(&mut validation_features).push_next(messenger_info);
        }
        *held() = Some(Vec::new());
        // SAFETY: every pointer in create_info refers to locals alive for this call.
        let created = unsafe { entry.create_instance(&create_info, None) };
        if created.is_ok() {
            print_held_messages();
        }
        let raw = created.map_err(|result| match result {
            vk::Result::ERROR_EXTENSION_NOT_PRESENT => Error::Environment(
                "the Vulkan loader lacks a required instance extension (VK_EXT_debug_utils or a surface extension)"
                    .into(),
            ),
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::Environment(
                "no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER): install one, such as \
                 mesa-vulkan-drivers (lavapipe)"
                    .into(),
            ),
            result => Error::vulkan("vkCreateInstance", result),
        })?;
        let debug_utils = has_debug_utils.then(|| ash::ext::debug_utils::Instance::new(&entry, &raw));
        let messenger = match (messenger_info, &debug_utils) {
            // SAFETY: the counter behind user_data is kept alive by `self.counter`. The create
            // info was chained into the instance's; unlink it before reusing it on its own.
            (Some(mut info), Some(debug_utils)) => match unsafe {
                info.p_next = std::ptr::null();
                debug_utils.create_debug_utils_messenger(&info, None)
            } {
                Ok(messenger) => messenger,
                Err(result) => {
                    // SAFETY: nothing was created from the instance yet.
                    unsafe { raw.destroy_instance(None) };
                    return Err(Error::vulkan("vkCreateDebugUtilsMessengerEXT", result));
                }
            },
            _ => vk::DebugUtilsMessengerEXT::null(),
        };
        Ok(Self { entry, raw, debug_utils, portability_enumeration, messenger, counter })
    }

    /// The validation counter, when validation is on. Keep a clone to read the final count after
    /// the instance is gone.
    pub fn validation_counter(&self) -> Option<Arc<ValidationCounter>> {
        self.counter.clone()
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: owners of device objects hold an Arc to this instance, so everything created from
        // it has been destroyed when the last reference drops.
        unsafe {
            if let (false, Some(debug_utils)) =
                (self.messenger == vk::DebugUtilsMessengerEXT::null(), &self.debug_utils)
            {
                debug_utils.destroy_debug_utils_messenger(self.messenger, None);
            }
            self.raw.destroy_instance(None);
        }
    }
}

/// While the instance is being created, messages (the loader's, when it finds no driver) are held
/// here instead of printed: a failure's `error:` line comes first, then what the loader said
/// ([`print_held_messages`]).
static HELD: std::sync::Mutex<Option<Vec<String>>> = std::sync::Mutex::new(None);

fn held() -> std::sync::MutexGuard<'static, Option<Vec<String>>> {
    HELD.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Print the messages held while an instance was being created (after its error, if it failed).
pub fn print_held_messages() {
    for line in held().take().unwrap_or_default() {
        eprintln!("{line}");
    }
}

/// Debug messenger callback: print the message on stderr (or hold it, see [`HELD`]) and count it.
unsafe extern "system" fn on_debug_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: user_data is the Arc<ValidationCounter> pointer given at creation, alive while the
    // instance is (the Instance holds a clone).
    if let Some(counter) = unsafe { (user_data as *const ValidationCounter).as_ref() } {
        counter.messages.fetch_add(1, Ordering::SeqCst);
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call.
    let (id, message) = unsafe {
        data.as_ref()
            .map(|d| {
                (
                    d.message_id_name_as_c_str().map(|s| s.to_string_lossy().into_owned()),
                    d.message_as_c_str().map(|s| s.to_string_lossy().into_owned()),
                )
            })
            .unwrap_or_default()
    };
    let line = format!(
        "validation [{severity:?} {kind:?}] {}: {}",
        id.as_deref().unwrap_or("-"),
        message.as_deref().unwrap_or("(no message)")
    );
    match held().as_mut() {
        Some(lines) => lines.push(line),
        None => eprintln!("{line}"),
    }
    vk::FALSE
}
