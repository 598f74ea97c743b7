//! Window surface and swapchain. Images are drawn by the renderer through a `TargetView`; each
//! image has its own "render finished" semaphore for presentation (a frame in flight's semaphore
//! could still be waited on by the presentation of an earlier image).

use std::sync::atomic::{AtomicUsize, Ordering};

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::{sync, Device};

/// Swapchains alive right now, and the most ever alive at once (tests check ≤ 2).
static ALIVE: AtomicUsize = AtomicUsize::new(0);
static MAX_ALIVE: AtomicUsize = AtomicUsize::new(0);
static CREATED: AtomicUsize = AtomicUsize::new(0);

/// (created, most alive at once) over the process.
pub fn swapchain_counts() -> (usize, usize) {
    (CREATED.load(Ordering::SeqCst), MAX_ALIVE.load(Ordering::SeqCst))
}

/// Presentation modes `--present` accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PresentMode {
    /// Vsync, always supported.
    #[default]
    Fifo,
    /// Latest image wins, no tearing.
    Mailbox,
    /// No waiting, may tear.
    Immediate,
}

impl PresentMode {
    fn raw(self) -> vk::PresentModeKHR {
        match self {
            PresentMode::Fifo => vk::PresentModeKHR::FIFO,
            PresentMode::Mailbox => vk::PresentModeKHR::MAILBOX,
            PresentMode::Immediate => vk::PresentModeKHR::IMMEDIATE,
        }
    }
}

/// A surface and its swapchain.
pub struct Swapchain {
    surface_fn: ash::khr::surface::Instance,
    swapchain_fn: ash::khr::swapchain::Device,
    /// The window surface.
    pub surface: vk::SurfaceKHR,
    /// The swapchain (null while the window has no area).
    pub raw: vk::SwapchainKHR,
    /// Its images.
    pub images: Vec<vk::Image>,
    /// One view per image.
    pub views: Vec<vk::ImageView>,
    /// One present ("render finished") semaphore per image.
    pub present_semaphores: Vec<vk::Semaphore>,
    /// Colour format (UNORM: the shaders encode sRGB, as offscreen).
    pub format: vk::Format,
    /// Current extent.
    pub extent: vk::Extent2D,
    /// Whether images can be copied out (TRANSFER_SRC supported).
    pub screenshots: bool,
    present_mode: vk::PresentModeKHR,
    /// The present modes the surface supports.
    modes: Vec<vk::PresentModeKHR>,
}

impl Swapchain {
    /// Wrap `surface` (created by the caller from the window) and check the device can present
    /// to it with `mode`.
    pub fn new(device: &Device, surface: vk::SurfaceKHR, mode: PresentMode) -> Result<Self> {
        let instance = &device.instance;
        let surface_fn = ash::khr::surface::Instance::new(&instance.entry, &instance.raw);
        let swapchain_fn = ash::khr::swapchain::Device::new(&instance.raw, &device.raw);
        // SAFETY: valid physical device, family and surface.
        let supported =
            unsafe { surface_fn.get_physical_device_surface_support(device.physical, device.queue_family, surface) }
                .vk("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(Error::Environment(format!("{} cannot present to this window", device.info.name)));
        }
        // SAFETY: as above.
        let modes = unsafe { surface_fn.get_physical_device_surface_present_modes(device.physical, surface) }
            .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        if !modes.contains(&mode.raw()) {
            return Err(Error::bad_input(format!("--present {mode:?}: not supported here (supported: {modes:?})")));
        }
        // SAFETY: as above.
        let formats = unsafe { surface_fn.get_physical_device_surface_formats(device.physical, surface) }
            .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        let format = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM]
            .into_iter()
            .find(|f| formats.iter().any(|s| s.format == *f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR))
            .ok_or_else(|| Error::Environment(format!("the surface offers no 8-bit UNORM format: {formats:?}")))?;
        Ok(Self {
            surface_fn,
            swapchain_fn,
            surface,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            views: Vec::new(),
            present_semaphores: Vec::new(),
            format,
            extent: vk::Extent2D::default(),
            screenshots: false,
            present_mode: mode.raw(),
            modes,
        })
    }

    /// The present modes the surface supports, of those meadow names.
    pub fn present_modes(&self) -> Vec<PresentMode> {
        [PresentMode::Fifo, PresentMode::Mailbox, PresentMode::Immediate]
            .into_iter()
            .filter(|m| self.modes.contains(&m.raw()))
            .collect()
    }

    /// Present with `mode` from the next re-creation on (the caller re-creates).
    pub fn set_present_mode(&mut self, mode: PresentMode) -> Result<()> {
        if !self.modes.contains(&mode.raw()) {
            return Err(Error::bad_input(format!("present mode {mode:?}: not supported here")));
        }
        self.present_mode = mode.raw();
        Ok(())
    }

    /// The present mode of the next re-creation.
    pub fn present_mode(&self) -> PresentMode {
        self.present_modes().into_iter().find(|m| m.raw() == self.present_mode).unwrap_or_default()
    }

    /// Create (or re-create, handing over the old one) the swapchain for a window of `size`.
    /// Returns false when the surface has no area (minimised): nothing to render into.
    ///
    /// The old swapchain, its views and present semaphores are handed back, not destroyed: frames
    /// in flight and the presentation engine may still use them (see [`Retired`]).
    pub fn recreate(&mut self, device: &Device, size: vk::Extent2D) -> Result<(bool, Retired)> {
        // SAFETY: valid physical device and surface.
        let caps = unsafe { self.surface_fn.get_physical_device_surface_capabilities(device.physical, self.surface) }
            .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size.width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size.height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut retired = self.retire();
        if extent.width == 0 || extent.height == 0 {
            retired.raw = std::mem::take(&mut self.raw);
            self.extent = extent;
            return Ok((false, retired));
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let old = self.raw;
        // Screenshots copy from the image: ask for TRANSFER_SRC only where the surface allows it.
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        if caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC) {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        self.screenshots = usage.contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
        ]
        .into_iter()
        .find(|a| caps.supported_composite_alpha.contains(*a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface)
            .min_image_count(count)
            .image_format(self.format)
            .image_color_space(vk::ColorSpaceKHR::SRGB_NONLINEAR)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(self.present_mode)
            .clipped(true)
            .old_swapchain(old);
        // SAFETY: valid create info; the old swapchain is retired by this call.
        let raw = super::live::created(
            unsafe { self.swapchain_fn.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?,
        );
        let alive = ALIVE.fetch_add(1, Ordering::SeqCst) + 1;
        MAX_ALIVE.fetch_max(alive, Ordering::SeqCst);
        CREATED.fetch_add(1, Ordering::SeqCst);
        retired.raw = old;
        self.raw = raw;
        self.extent = extent;
        device.set_name(raw, "swapchain");
        self.create_views(device)?;
        Ok((true, retired))
    }

    /// The new swapchain's images, a view and a present semaphore for each.
    fn create_views(&mut self, device: &Device) -> Result<()> {
        // SAFETY: raw is valid.
        self.images = unsafe { self.swapchain_fn.get_swapchain_images(self.raw) }.vk("vkGetSwapchainImagesKHR")?;
        for (i, image) in self.images.iter().enumerate() {
            device.set_name(*image, &format!("swapchain image {i}"));
            let view_info = vk::ImageViewCreateInfo::default()
                .image(*image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(self.format)
                .subresource_range(crate::vk::image::COLOR_RANGE);
            // SAFETY: the image belongs to the swapchain.
            let view = super::live::created(
                unsafe { device.raw.create_image_view(&view_info, None) }.vk("vkCreateImageView")?,
            );
            device.set_name(view, &format!("swapchain view {i}"));
            self.views.push(view);
            self.present_semaphores.push(sync::semaphore(device, &format!("present semaphore {i}"))?);
        }
        Ok(())
    }

    /// Take the views and present semaphores out, to be destroyed later (the swapchain handle
    /// is added by `recreate` once the new swapchain exists).
    fn retire(&mut self) -> Retired {
        self.images.clear();
        Retired {
            swapchain_fn: self.swapchain_fn.clone(),
            raw: vk::SwapchainKHR::null(),
            views: std::mem::take(&mut self.views),
            present_semaphores: std::mem::take(&mut self.present_semaphores),
        }
    }

    /// Acquire the next image, signalling `semaphore`. `Ok(None)` means out of date: recreate.
    pub fn acquire(&self, semaphore: vk::Semaphore) -> Result<Option<(u32, bool)>> {
        if super::fault::fails(super::fault::Fault::Acquire) {
            // Before the call: the semaphore stays unsignalled, as after a real failure.
            return Err(Error::vulkan("vkAcquireNextImageKHR (injected failure)", vk::Result::ERROR_SURFACE_LOST_KHR));
        }
        // SAFETY: the semaphore is unsignalled with no pending wait (its frame's fence was waited).
        match unsafe { self.swapchain_fn.acquire_next_image(self.raw, u64::MAX, semaphore, vk::Fence::null()) } {
            Ok((index, suboptimal)) => Ok(Some((index, suboptimal))),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(result) => Err(Error::vulkan("vkAcquireNextImageKHR", result)),
        }
    }

    /// Present `index`, waiting on its present semaphore. `Ok(false)`: out of date or suboptimal.
    pub fn present(&self, device: &Device, index: u32) -> Result<bool> {
        let semaphores = [self.present_semaphores[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&semaphores).swapchains(&swapchains).image_indices(&indices);
        if super::fault::fails(super::fault::Fault::Present) {
            // The call is made (the semaphore's wait is consumed), its result replaced.
            // SAFETY: as below.
            let _ = unsafe { self.swapchain_fn.queue_present(device.queue, &info) };
            return Err(Error::vulkan("vkQueuePresentKHR (injected failure)", vk::Result::ERROR_SURFACE_LOST_KHR));
        }
        // SAFETY: the image was acquired and rendered; the semaphore is signalled by that submission.
        match unsafe { self.swapchain_fn.queue_present(device.queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(result) => Err(Error::vulkan("vkQueuePresentKHR", result)),
        }
    }

    fn destroy_views(&mut self, device: &Device) {
        // SAFETY: the caller waited for all work on these views and semaphores.
        unsafe {
            for view in self.views.drain(..) {
                super::live::destroyed(view);
                device.raw.destroy_image_view(view, None);
            }
            for semaphore in self.present_semaphores.drain(..) {
                super::live::destroyed(semaphore);
                device.raw.destroy_semaphore(semaphore, None);
            }
        }
        self.images.clear();
    }

    fn destroy_swapchain(&mut self) {
        destroy_swapchain(&self.swapchain_fn, std::mem::take(&mut self.raw));
    }

    /// Destroy the swapchain, its views and semaphores, and the surface.
    ///
    /// # Safety
    /// The device must be idle.
    pub unsafe fn destroy(mut self, device: &Device) {
        self.destroy_views(device);
        self.destroy_swapchain();
        // SAFETY: nothing uses the surface any more.
        unsafe {
            super::live::destroyed(self.surface);
            self.surface_fn.destroy_surface(self.surface, None)
        };
    }
}

/// Destroy a swapchain (null: nothing) and count it.
fn destroy_swapchain(swapchain_fn: &ash::khr::swapchain::Device, raw: vk::SwapchainKHR) {
    if raw != vk::SwapchainKHR::null() {
        // SAFETY: the callers' contracts: no pending work uses its images.
        unsafe {
            super::live::destroyed(raw);
            swapchain_fn.destroy_swapchain(raw, None)
        };
        ALIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// What a re-creation replaced. Two lifetimes, two rules:
/// - the views are used by the command buffers of the frames in flight: destroy them once the
///   last frame submitted before the re-creation has finished (its fence);
/// - the swapchain and its present semaphores are used by presentations, which no fence covers
///   without `VK_EXT_swapchain_maintenance1`: destroy them once as many frames as there are
///   images, plus the frames in flight, have completed since — by then every presentation
///   queued before the re-creation has been followed by that many later ones on the same queue.
///   This is a rule of thumb the spec does not guarantee; the extension's present fences would.
pub struct Retired {
    swapchain_fn: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    views: Vec<vk::ImageView>,
    present_semaphores: Vec<vk::Semaphore>,
}

impl Retired {
    /// Number of present semaphores retired (the images of the old swapchain).
    pub fn images(&self) -> usize {
        self.present_semaphores.len()
    }

    /// Split into the views, and the swapchain with its present semaphores.
    pub fn split(self) -> (RetiredViews, RetiredPresentation) {
        (
            RetiredViews { views: self.views },
            RetiredPresentation { swapchain_fn: self.swapchain_fn, raw: self.raw, semaphores: self.present_semaphores },
        )
    }
}

/// A retired swapchain's image views.
pub struct RetiredViews {
    views: Vec<vk::ImageView>,
}

impl RetiredViews {
    /// Destroy the views.
    ///
    /// # Safety
    /// No command buffer using them may be pending.
    pub unsafe fn destroy(self, device: &Device) {
        for view in self.views {
            // SAFETY: per the contract.
            unsafe {
                super::live::destroyed(view);
                device.raw.destroy_image_view(view, None)
            };
        }
    }
}

/// A retired swapchain and its present semaphores.
pub struct RetiredPresentation {
    swapchain_fn: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    semaphores: Vec<vk::Semaphore>,
}

impl RetiredPresentation {
    /// Destroy the semaphores and the swapchain.
    ///
    /// # Safety
    /// No presentation may still use them (and no command buffer its images).
    pub unsafe fn destroy(self, device: &Device) {
        for semaphore in self.semaphores {
            // SAFETY: per the contract.
            unsafe {
                super::live::destroyed(semaphore);
                device.raw.destroy_semaphore(semaphore, None)
            };
        }
        destroy_swapchain(&self.swapchain_fn, self.raw);
    }
}
