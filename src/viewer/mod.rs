//! `meadow view`: the interactive viewer. The same renderer and passes as `meadow render`, drawn
//! into a swapchain with frames in flight; a free camera; live wind, source, collider and mode
//! controls; stats; a script for reproducible sessions.

pub mod controls;
mod emitters;
mod events;
mod keys;
mod outputs;
mod overlay;
mod rebuild;
pub mod script;
mod session;
mod stats;
mod surface;
mod ui;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::raw_window_handle::HasDisplayHandle;
use winit::window::Window;

use crate::app::{self, GpuOptions, RenderOptions};
use crate::error::{Error, Result, VkContext};
use crate::render::frame::Deletion;
use crate::render::graph::Outputs;
use crate::render::{RenderSettings, Renderer};
use crate::scene::Scene;
use crate::vk::swapchain::{swapchain_counts, PresentMode, Swapchain};
use crate::vk::{Device, Guard, Image, ImageDesc, Resource, SurfaceGuard};
use crate::wind::CalmArea;
use controls::CameraControl;
use script::Script;
use stats::Stats;
use surface::Surface;

/// The message when there is no display, and its exit code (2).
pub const NO_DISPLAY: &str = "no display (set DISPLAY or WAYLAND_DISPLAY, or run under xvfb-run)";

/// What `meadow view` is started with.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Scene, animation and window size (`size`), as for `meadow render`.
    pub scene: RenderOptions,
    /// Presentation mode.
    pub present: PresentMode,
    /// Frames in flight, 1..=3.
    pub frames_in_flight: usize,
    /// Quit after this many rendered frames.
    pub frames: Option<u64>,
    /// Timed actions.
    pub script: Option<Script>,
    /// Write the last frame to this PNG at exit.
    pub screenshot: Option<PathBuf>,
    /// Pretend the swapchain is out of date every N frames (lavapipe never reports it).
    pub inject_out_of_date: Option<u32>,
    /// Print a `sample:` line (resident memory, live Vulkan objects) every N frames (the soak).
    pub sample_every: Option<u64>,
    /// Show the overlay (`--no-ui`: false).
    pub ui: bool,
    /// Screenshots include the overlay.
    pub screenshot_ui: bool,
    /// Where the overlay's captures go (checked at start).
    pub capture_dir: Option<PathBuf>,
}

/// What a viewer session did.
#[derive(Clone, Debug, Default)]
pub struct ViewerReport {
    /// Frames rendered.
    pub frames: u64,
    /// Swapchains created, and the most alive at once.
    pub swapchains: (usize, usize),
    /// Times the swapchain was re-created.
    pub recreations: u64,
    /// Of those, the ones `--inject-out-of-date` caused (the others follow the window system).
    pub injected: u64,
    /// The last stats line.
    pub stats: String,
    /// The present mode the swapchain ran with (`None`: no swapchain was made).
    pub present: Option<PresentMode>,
    /// Frames in flight.
    pub frames_in_flight: usize,
    /// Whether the overlay was drawn (`--no-ui`: not).
    pub overlay: bool,
}

/// Run the viewer; returns its report and the validation message count.
pub fn run(gpu: &GpuOptions, options: ViewerOptions) -> (Result<ViewerReport>, Option<u64>) {
    // Every output the session will write, checked before any work.
    if let Err(e) = outputs::check(&options) {
        return (Err(e), None);
    }
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    if !set("DISPLAY") && !set("WAYLAND_DISPLAY") {
        return (Err(Error::bad_input(NO_DISPLAY)), None);
    }
    let event_loop = match EventLoop::new() {
        Ok(event_loop) => event_loop,
        Err(e) => {
            log::debug!("event loop: {e}");
            return (Err(Error::bad_input(NO_DISPLAY)), None);
        }
    };
    let extensions =
        match event_loop.display_handle().map_err(|e| Error::bad_input(format!("{NO_DISPLAY}: {e}"))).and_then(|h| {
            ash_window::enumerate_required_extensions(h.as_raw()).vk("vkEnumerateInstanceExtensionProperties")
        }) {
            Ok(extensions) => extensions,
            Err(e) => return (Err(e), None),
        };
    app::with_instance(gpu, extensions, |instance| {
        let mut session = session::Session::new(instance, gpu.device.clone(), options);
        event_loop.run_app(&mut session).map_err(|e| Error::Environment(format!("event loop: {e}")))?;
        session.finish()
    })
}

/// The swapchain, its depth image, and the window they belong to. Dropped in that order.
struct Viewer {
    device: Arc<Device>,
    options: ViewerOptions,
    scene: Scene,
    settings: RenderSettings,
    renderer: Option<Renderer>,
    surface: Option<Surface>,
    control: CameraControl,
    script: Script,
    calm_off: Option<Vec<CalmArea>>,
    /// F7: a sphere under the eye tramples the grass (`emitters`, added for each frame).
    trample: bool,
    /// F4's slope limit, in degrees (`--slope-limit`, or `keys::DEFAULT_SLOPE_LIMIT_DEG`).
    slope_limit_deg: f32,
    /// F5's clump size, in metres (`--clumps`, or `keys::DEFAULT_CLUMP_SIZE_M`).
    clump_size_m: f32,
    /// F6's flowers per m² (`--flowers`, or `keys::DEFAULT_FLOWERS_PER_M2`).
    flowers_per_m2: f32,
    /// Simulated time, in whole steps of `--dt` (at most 4 a frame).
    clock: crate::render::animation::clock::StepPacer,
    paused: bool,
    fixed_step: bool,
    tick: u64,
    frames: u64,
    recreations: u64,
    needs_recreate: bool,
    minimised: bool,
    screenshot: Option<PathBuf>,
    screenshots_taken: u32,
    cursor: (f64, f64),
    dragging: bool,
    last_tick: Instant,
    stats: Stats,
    /// `--budget-ms`: the loop setting the LOD scale from the measured GPU time.
    budget: Option<crate::render::budget::FrameBudget>,
    /// The last render call was an injected out-of-date result (`--inject-out-of-date`).
    injected_last: bool,
    /// Out-of-date results injected so far.
    injected: u64,
    /// The overlay (`None` with `--no-ui`).
    ui: Option<ui::Ui>,
    /// What the overlay's controls asked for, applied before the next frame.
    ui_actions: Vec<ui::UiAction>,
    /// A trace capture in progress, and how many were written.
    capture: Option<overlay::Capture>,
    captures_written: u32,
    error: Option<Error>,
    quit: bool,
}

impl Viewer {
    fn new(device: Arc<Device>, options: ViewerOptions) -> Result<Self> {
        let o = &options.scene;
        o.check_field()?;
        if o.field.is_some() {
            for (frame, action) in options.script.iter().flat_map(|s| &s.actions) {
                if let script::Action::Camera(camera) = action {
                    crate::scene::field::check_camera(camera.position)
                        .map_err(|e| Error::bad_input(format!("--script: frame {frame}: {e}")))?;
                }
            }
        }
        crate::app::check_limits(
            &device,
            o.stored_blades(),
            (o.size, o.msaa, o.offscreen_settings(1).linear_scene()),
            crate::scene::Terrain::cells_for(crate::scene::blades::field_size(o.stored_blades())),
        )?;
        let scene = o.scene()?;
        let camera = scene.camera(o.camera);
        // The options' settings, into the swapchain's format; statistics queries for the
        // overlay's timing panel (none with --no-ui, for measurements).
        let settings = RenderSettings {
            color_format: vk::Format::B8G8R8A8_UNORM,
            pipeline_statistics: options.ui,
            ..o.offscreen_settings(options.frames_in_flight)
        };
        let fixed_step = options.script.is_some() || options.frames.is_some();
        Ok(Self {
            device,
            scene,
            settings,
            renderer: None,
            surface: None,
            control: CameraControl::new(camera),
            script: options.script.clone().unwrap_or_default(),
            calm_off: None,
            trample: false,
            slope_limit_deg: o.landscape.slope_limit_deg.unwrap_or(keys::DEFAULT_SLOPE_LIMIT_DEG),
            clump_size_m: o.clumps.map_or(keys::DEFAULT_CLUMP_SIZE_M, |c| c.size_m),
            flowers_per_m2: o.flowers.map_or(keys::DEFAULT_FLOWERS_PER_M2, |f| f.per_m2),
            clock: crate::render::animation::clock::StepPacer::new(o.animation.clock, o.time.into()),
            paused: false,
            fixed_step,
            tick: 0,
            frames: 0,
            recreations: 0,
            needs_recreate: false,
            minimised: false,
            screenshot: None,
            screenshots_taken: 0,
            cursor: (0.0, 0.0),
            dragging: false,
            last_tick: Instant::now(),
            stats: Stats::new(),
            injected_last: false,
            injected: 0,
            ui: None,
            ui_actions: Vec::new(),
            capture: None,
            captures_written: 0,
            budget: options
                .scene
                .budget_ms
                .map(|ms| crate::render::budget::FrameBudget::new(ms, options.scene.culling.lod_scale)),
            error: None,
            quit: false,
            options,
        })
    }

    /// Tear down in order, take the exit screenshot's result, and report.
    fn finish(&mut self) -> Result<ViewerReport> {
        let result = match self.error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        };
        let present = self.surface.as_ref().map(|s| s.swapchain.present_mode());
        self.teardown();
        result?;
        Ok(ViewerReport {
            frames: self.frames,
            swapchains: swapchain_counts(),
            recreations: self.recreations,
            injected: self.injected,
            stats: self.stats.last.clone(),
            present,
            frames_in_flight: self.options.frames_in_flight,
            overlay: self.ui.is_some(),
        })
    }

    fn teardown(&mut self) {
        if let Some(renderer) = &mut self.renderer {
            let _ = renderer.wait_all_frames();
        }
        // SAFETY: queue idle: every frame and presentation using the swapchain is done.
        let _ = unsafe { self.device.raw.queue_wait_idle(self.device.queue) };
        self.renderer = None;
        if let Some(surface) = self.surface.take() {
            // SAFETY: the queue is idle.
            unsafe {
                if let Some(depth) = surface.depth {
                    depth.destroy(&self.device);
                }
                surface.swapchain.destroy(&self.device);
            }
            drop(surface.window);
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        event_loop.exit();
    }

    /// The shared checks of a scene of `blades` with `animation` and the current settings, at the
    /// window's size (`app::check_scene`), before a renderer is built or rebuilt.
    fn check_scene(&self, blades: u32, animation: &crate::render::animation::AnimationSettings) -> Result<()> {
        let size = self
            .surface
            .as_ref()
            .map_or(self.options.scene.size, |s| (s.swapchain.extent.width.max(1), s.swapchain.extent.height.max(1)));
        let settings = &self.settings;
        crate::app::check_scene(
            &self.device,
            blades,
            settings.segments,
            size,
            animation,
            settings.floor,
            (settings.culling.enabled, settings.msaa, settings.linear_scene()),
        )
    }

    /// Build the renderer for `animation` and the current settings, after the shared checks.
    fn build_renderer(&mut self, animation: crate::render::animation::AnimationSettings) -> Result<()> {
        self.check_scene(self.scene.blades.len() as u32, &animation)?;
        crate::app::check_timestamps_for_budget(&self.device, self.options.scene.budget_ms)?;
        self.renderer = Some(Renderer::new(self.device.clone(), &self.scene, self.settings, animation)?);
        if let Some(ui) = self.ui.as_mut() {
            ui.renderer_replaced();
        }
        Ok(())
    }

    /// Take the window and its surface (`session`, which chose the device for it): the swapchain,
    /// its depth image and the renderer. The surface is destroyed on failure.
    fn adopt(&mut self, window: Window, raw: vk::SurfaceKHR) -> Result<()> {
        let raw = SurfaceGuard::new(&self.device.instance, raw);
        let swapchain = Swapchain::new(&self.device, *raw, self.options.present)?;
        raw.take();
        self.settings.color_format = swapchain.format;
        self.make_ui(&window);
        self.surface = Some(Surface { swapchain, depth: None, depth_used: false, window });
        self.recreate()?;
        self.build_renderer(self.options.scene.animation.clone())
    }

    /// (Re)create the swapchain and depth image at the window's size, without waiting for the
    /// queue: the old views and depth image are destroyed once the frames submitted before have
    /// finished, the old swapchain and its present semaphores once enough later frames have
    /// completed (`vk::swapchain::Retired`). A re-creation while earlier objects are still queued
    /// (a resize storm) waits for the frames and the queue first, so at most two swapchains exist.
    fn recreate(&mut self) -> Result<()> {
        let surface = self.surface.as_mut().expect("surface exists");
        let old_depth = surface.depth.take();
        let old_images = surface.swapchain.images.clone();
        let size = surface.window.inner_size();
        let in_flight = self.settings.frames_in_flight as u64;
        if let Some(renderer) = self.renderer.as_mut() {
            if renderer.pending_deletions() > 0 {
                // Retired faster than frames complete (a resize storm): at most two swapchains.
                renderer.drain_deletions()?;
            }
            // Recordings and tracked states name the old images; their handles may be reused.
            renderer.forget_recordings();
            for image in &old_images {
                renderer.forget(Resource::color(*image));
            }
            if let Some(depth) = &old_depth {
                renderer.forget(Resource::depth(depth.raw));
            }
        }
        self.retire(old_depth.map(|depth| {
            Box::new(move |device: &Device| {
                // SAFETY: the frames submitted before the re-creation have finished.
                unsafe { depth.destroy(device) }
            }) as Deletion
        }));
        let surface = self.surface.as_mut().expect("surface exists");
        let (has_area, retired) =
            surface.swapchain.recreate(&self.device, vk::Extent2D { width: size.width, height: size.height })?;
        let images = retired.images() as u64;
        let (views, presentation) = retired.split();
        // SAFETY (when run): the frames submitted before the re-creation have finished.
        self.retire(Some(Box::new(move |device| unsafe { views.destroy(device) })));
        // SAFETY (when run): presentations queued before were followed by `images + in_flight`
        // completed frames (`vk::swapchain::Retired`).
        let presentation: Deletion = Box::new(move |device| unsafe { presentation.destroy(device) });
        match self.renderer.as_mut() {
            Some(renderer) => renderer.defer_frames(images + in_flight, presentation),
            None => presentation(&self.device),
        }
        self.minimised = !has_area;
        if has_area {
            let surface = self.surface.as_mut().expect("surface exists");
            let extent = surface.swapchain.extent;
            surface.depth =
                Some(Image::new(&self.device, &ImageDesc::depth("swapchain depth", self.device.depth_format, extent))?);
            surface.depth_used = false;
        }
        self.needs_recreate = false;
        self.recreations += 1;
        Ok(())
    }

    /// Destroy `deletion` once the frames submitted so far have finished (now without a renderer:
    /// nothing was submitted).
    fn retire(&mut self, deletion: Option<Deletion>) {
        match (deletion, self.renderer.as_mut()) {
            (Some(deletion), Some(renderer)) => renderer.defer(deletion),
            (Some(deletion), None) => deletion(&self.device),
            (None, _) => {}
        }
    }

    /// Render one frame into the swapchain.
    fn render(&mut self) -> Result<()> {
        // `--inject-out-of-date N`: an out-of-date result before every N-th presented frame, never
        // twice in a row (so N = 1 alternates), and never counted as a presented frame.
        let inject = !self.injected_last
            && self.options.inject_out_of_date.is_some_and(|n| self.frames % u64::from(n) == u64::from(n) - 1);
        if self.needs_recreate || inject {
            self.recreate()?;
            if inject {
                self.injected_last = true;
                self.injected += 1;
                return Ok(());
            }
            if self.minimised {
                return Ok(());
            }
        }
        // Never used by the GPU until the frame is submitted.
        let device = self.device.clone();
        let readback = Guard::new(&device, self.screenshot_buffer()?);
        let begun = self.renderer.as_mut().expect("renderer built").begin_frame();
        let begun = begun.and_then(|(slot, timings)| self.frame_begun(timings, readback.is_some()).map(|()| slot));
        let slot = begun?;
        let renderer = self.renderer.as_mut().expect("renderer built");
        let surface = self.surface.as_mut().expect("surface exists");
        let acquired = surface.swapchain.acquire(renderer.acquire_semaphore(slot));
        let Ok(Some((index, suboptimal))) = acquired else {
            self.needs_recreate = true;
            return acquired.map(|_| ());
        };
        let view = surface.target_view(index);
        let sync = crate::render::renderer::FrameSync {
            wait: Some(renderer.acquire_semaphore(slot)),
            signal: Some(surface.swapchain.present_semaphores[index as usize]),
        };
        let readback = readback.take();
        let outputs = Outputs { readback: readback.as_ref().map(|b| b.raw), present: true };
        let submitted =
            renderer.submit_frame(slot, &view, &self.control.camera, self.clock.time() as f32, sync, outputs);
        if submitted.is_err() {
            // The acquired image was never rendered nor presented: release it with a new swapchain.
            self.needs_recreate = true;
        } else {
            surface.depth_used |= renderer.uses_target_depth();
        }
        let result = submitted.and_then(|()| surface.swapchain.present(&self.device, index));
        if let (Some(buffer), Some(path)) = (readback, self.screenshot.take()) {
            // A screenshot is rare: wait for this frame, then write the picture (only of a frame
            // that ran).
            let written = if result.is_ok() { surface.write_screenshot(renderer, &buffer, &path) } else { Ok(()) };
            // SAFETY: the frame that wrote it completed, or it was never submitted (the wait of
            // a failed frame's new fence returns at once; the renderer's drop waits for the rest).
            unsafe { buffer.destroy(&self.device) };
            written?;
        }
        if !result? || suboptimal {
            self.needs_recreate = true;
        }
        self.frames += 1;
        self.injected_last = false;
        if self.options.sample_every.is_some_and(|n| self.frames.is_multiple_of(n)) {
            println!("{}", stats::sample(self.frames));
        }
        let (blades, terrain) = renderer.triangles();
        self.stats.tick(&surface.window, renderer.blade_count(), blades + terrain, &self.device.info.name);
        Ok(())
    }
}

impl Drop for Viewer {
    /// Every exit path (an event-loop error included) releases the swapchain, surface and depth
    /// image before the device goes.
    fn drop(&mut self) {
        self.teardown();
    }
}
