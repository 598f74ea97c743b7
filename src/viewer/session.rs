//! The viewer's start: the window and its surface exist before the device, so that the device
//! chosen is one whose queue can present to that surface (`vkGetPhysicalDeviceSurfaceSupportKHR`),
//! not the first with `VK_KHR_swapchain`. Winit creates windows once the event loop runs
//! (`resumed`), so the session starts there and then hands every event to the viewer.

use std::sync::Arc;

use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use super::keys::HELP;
use super::{Viewer, ViewerOptions, ViewerReport};
use crate::error::{Error, Result, VkContext};
use crate::vk::device::{DeviceDesc, DeviceSelector};
use crate::vk::{Device, Instance, SurfaceGuard};

/// Where a viewer session is.
pub(super) enum Session {
    /// Before the window: what the viewer is started with.
    Starting { instance: Arc<Instance>, selector: DeviceSelector, options: Box<ViewerOptions> },
    /// The window, device and viewer exist.
    Running(Box<Viewer>),
    /// Starting failed (nothing is left to tear down).
    Failed(Error),
}

impl Session {
    /// A session that will open its window and choose its device when the event loop starts.
    pub(super) fn new(instance: Arc<Instance>, selector: DeviceSelector, options: ViewerOptions) -> Self {
        Session::Starting { instance, selector, options: Box::new(options) }
    }

    /// The viewer's report, or why the session failed.
    pub(super) fn finish(self) -> Result<ViewerReport> {
        match self {
            Session::Running(mut viewer) => viewer.finish(),
            Session::Failed(e) => Err(e),
            Session::Starting { .. } => Err(Error::Environment("the event loop ended before the window opened".into())),
        }
    }

    /// Open the window, make its surface, choose a device that can present to it, and start the
    /// viewer on them.
    fn start(
        instance: Arc<Instance>,
        selector: DeviceSelector,
        options: ViewerOptions,
        event_loop: &ActiveEventLoop,
    ) -> Result<Viewer> {
        let (w, h) = options.scene.size;
        check_window_size(&instance, &selector, (w, h), event_loop)?;
        let attributes = Window::default_attributes().with_title("meadow").with_inner_size(PhysicalSize::new(w, h));
        let window = event_loop.create_window(attributes).map_err(|e| Error::Environment(format!("window: {e}")))?;
        // Destroyed if the device or the viewer cannot be made; the viewer owns it from `adopt`
        // (destroyed with its swapchain, or on failure).
        let raw = SurfaceGuard::new(&instance, surface(&instance, &window)?);
        let desc = DeviceDesc { selector, swapchain: true, surface: Some(*raw) };
        let device = Device::new(instance.clone(), &desc)?;
        let mut viewer = Viewer::new(device, options)?;
        println!("{HELP}");
        viewer.adopt(window, raw.take())?;
        Ok(viewer)
    }
}

/// Largest window side winit's X11 backend takes: the protocol's 16-bit sizes (`CARD16`); winit
/// panics past it. Wayland's sizes are 32-bit.
const X11_MAX_SIDE: u32 = u16::MAX as u32;

/// Refuse a window size the device cannot render at or the platform cannot make, before the
/// window exists (exit 2).
fn check_window_size(
    instance: &Instance,
    selector: &DeviceSelector,
    (w, h): (u32, u32),
    event_loop: &ActiveEventLoop,
) -> Result<()> {
    let device = crate::vk::device::window_side_limit(instance, selector)?;
    if w > device || h > device {
        return Err(Error::bad_input(format!(
            "--size {w}x{h} exceeds the device's maxImageDimension2D/maxFramebufferWidth of {device}"
        )));
    }
    use winit::platform::x11::ActiveEventLoopExtX11;
    let (platform, name) = match event_loop.is_x11() {
        true => (X11_MAX_SIDE, "an X11 window"),
        false => (i32::MAX as u32, "a window"),
    };
    if w > platform || h > platform {
        return Err(Error::bad_input(format!("--size {w}x{h}: {name} is at most {platform} pixels a side")));
    }
    Ok(())
}

/// The window's Vulkan surface.
fn surface(instance: &Instance, window: &Window) -> Result<vk::SurfaceKHR> {
    let display = window.display_handle().map_err(|e| Error::Environment(format!("window: {e}")))?;
    let handle = window.window_handle().map_err(|e| Error::Environment(format!("window: {e}")))?;
    // SAFETY: the window outlives the surface (the viewer drops the swapchain and surface first).
    unsafe { ash_window::create_surface(&instance.entry, &instance.raw, display.as_raw(), handle.as_raw(), None) }
        .vk("vkCreate*SurfaceKHR")
        .map(crate::vk::live::created)
}

impl ApplicationHandler for Session {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let placeholder = Session::Failed(Error::Environment("starting".into()));
        *self = match std::mem::replace(self, placeholder) {
            Session::Starting { instance, selector, options } => {
                match Session::start(instance, selector, *options, event_loop) {
                    Ok(viewer) => Session::Running(Box::new(viewer)),
                    Err(e) => {
                        event_loop.exit();
                        Session::Failed(e)
                    }
                }
            }
            other => other,
        };
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, id: WindowId, event: WindowEvent) {
        if let Session::Running(viewer) = self {
            viewer.window_event(event_loop, id, event);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Session::Running(viewer) = self {
            viewer.about_to_wait(event_loop);
        }
    }
}
