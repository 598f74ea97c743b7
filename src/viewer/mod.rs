//! `meadow view`: the interactive viewer. The same renderer and passes as `meadow render`, drawn
//! into a swapchain with frames in flight; a free camera; live wind, source, collider and mode
//! controls; stats; a script for reproducible sessions.

pub mod controls;
pub mod script;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use glam::{Vec2, Vec3, Vec4};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::app::{self, GpuOptions, RenderOptions};
use crate::error::{Error, Result, VkContext};
use crate::keyframes::Smoothing;
use crate::render::animation::{Eval, Mode};
use crate::render::graph::Outputs;
use crate::render::target::{TargetView, DEPTH_FORMAT};
use crate::render::{FrameTimings, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::swapchain::{swapchain_counts, PresentMode, Swapchain};
use crate::vk::{Access, Buffer, BufferDesc, Device, Image, ImageDesc};
use crate::wind::{CalmArea, Collider, PointSource};
use controls::CameraControl;
use script::{Action, Script};

/// The message when there is no display, and its exit code (2).
pub const NO_DISPLAY: &str = "no display (set DISPLAY or WAYLAND_DISPLAY, or run under xvfb-run)";

/// Set by Ctrl-C: the viewer closes cleanly at the next tick.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

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
    /// The last stats line.
    pub stats: String,
}

const HELP: &str = "\
meadow viewer controls
  W A S D / Q E   move / down, up       right mouse drag  look
  Shift           faster                 wheel             speed
  G               walk on the ground     H                 this help
  M               mode static/texture/uniform/floor   N  smoothing nearest/linear/slerp
  B               evaluation per vertex / per blade (compute)
  + / -           segments               [ / ]             blades / 2, x 2
  J / L           wind direction -/+15   I / K             wind strength +/-
  U               gusts on/off           C                 calm areas on/off
  left click      drop a wind source (drag to move)   Delete  remove the last source
  arrow keys      drive the collider sphere through the grass
  V               force debug view       F                 wireframe
  P               pause time             F12               screenshot
  Esc             quit";

/// Run the viewer; returns its report and the validation message count.
pub fn run(gpu: &GpuOptions, options: ViewerOptions) -> (Result<ViewerReport>, Option<u64>) {
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
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    app::with_device_extensions(gpu, extensions, true, |device| {
        let mut viewer = Viewer::new(device.clone(), options)?;
        event_loop.run_app(&mut viewer).map_err(|e| Error::Environment(format!("event loop: {e}")))?;
        viewer.finish()
    })
}

/// Frame statistics, reported twice a second in the title and every few seconds on stdout.
struct Stats {
    since_title: Instant,
    since_print: Instant,
    frames: u32,
    cpu_ms: f64,
    gpu_ms: f64,
    passes: Vec<(&'static str, f64)>,
    last: String,
}

impl Stats {
    fn new() -> Self {
        Self {
            since_title: Instant::now(),
            since_print: Instant::now(),
            frames: 0,
            cpu_ms: 0.0,
            gpu_ms: 0.0,
            passes: Vec::new(),
            last: String::new(),
        }
    }

    fn add(&mut self, t: &FrameTimings) {
        self.frames += 1;
        self.cpu_ms += t.cpu_record_ms + t.cpu_submit_ms + t.cpu_wait_ms;
        self.gpu_ms += t.gpu_ms;
        for p in &t.passes {
            match self.passes.iter_mut().find(|(n, _)| *n == p.name) {
                Some(entry) => entry.1 += p.ms,
                None => self.passes.push((p.name, p.ms)),
            }
        }
    }

    /// Every half second: the averages since the last line, for the title (and every 3 s, stdout).
    fn tick(&mut self, window: &Window, blades: u32, triangles: u64, device: &str) {
        let elapsed = self.since_title.elapsed().as_secs_f64();
        if elapsed < 0.5 || self.frames == 0 {
            return;
        }
        let n = f64::from(self.frames);
        let passes: Vec<String> = self.passes.iter().map(|(name, ms)| format!("{name} {:.2}", ms / n)).collect();
        self.last = format!(
            "{:.1} fps, cpu {:.2} ms, gpu {:.2} ms ({}), {blades} blades, {triangles} triangles, {device}",
            n / elapsed,
            self.cpu_ms / n,
            self.gpu_ms / n,
            passes.join(", ")
        );
        window.set_title(&format!("meadow - {}", self.last));
        if self.since_print.elapsed() >= Duration::from_secs(3) {
            println!("stats: {}", self.last);
            self.since_print = Instant::now();
        }
        *self = Self { since_print: self.since_print, last: std::mem::take(&mut self.last), ..Self::new() };
    }
}

/// The swapchain, its depth image, and the window they belong to. Dropped in that order.
struct Surface {
    swapchain: Swapchain,
    depth: Option<Image>,
    depth_used: bool,
    window: Window,
}

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
    time: f32,
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
    error: Option<Error>,
    quit: bool,
}

impl Viewer {
    fn new(device: Arc<Device>, options: ViewerOptions) -> Result<Self> {
        let o = &options.scene;
        crate::app::check_limits(
            &device,
            o.blades,
            o.size,
            crate::scene::Terrain::cells_for(crate::scene::blades::field_size(o.blades)),
        )?;
        let scene = Scene::generate(o.blades, o.seed);
        let camera = o.camera.unwrap_or_else(|| Camera::default_for(&scene.terrain));
        let settings = RenderSettings {
            segments: o.segments,
            color_format: vk::Format::B8G8R8A8_UNORM,
            encode_srgb: true,
            frames_in_flight: options.frames_in_flight,
            blades_per_instance: o.blades_per_instance,
            debug_force: o.debug_force,
            wireframe: false,
            pipeline_statistics: false,
            submission: Default::default(),
            debug_bounds: false,
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
            time: o.time,
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
        self.teardown();
        result?;
        Ok(ViewerReport {
            frames: self.frames,
            swapchains: swapchain_counts(),
            recreations: self.recreations,
            stats: self.stats.last.clone(),
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

    /// Build the renderer for `animation` and the current settings, after the shared checks.
    fn build_renderer(&mut self, animation: crate::render::animation::AnimationSettings) -> Result<()> {
        let size = self
            .surface
            .as_ref()
            .map_or(self.options.scene.size, |s| (s.swapchain.extent.width.max(1), s.swapchain.extent.height.max(1)));
        let blades = self.scene.blades.len() as u32;
        crate::app::check_scene(&self.device, blades, self.settings.segments, size, &animation)?;
        self.renderer = Some(Renderer::new(self.device.clone(), &self.scene, self.settings, animation)?);
        Ok(())
    }

    fn create_surface(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (w, h) = self.options.scene.size;
        let attributes = Window::default_attributes().with_title("meadow").with_inner_size(PhysicalSize::new(w, h));
        let window = event_loop.create_window(attributes).map_err(|e| Error::Environment(format!("window: {e}")))?;
        let instance = &self.device.instance;
        let display = window.display_handle().map_err(|e| Error::Environment(format!("window: {e}")))?;
        let handle = window.window_handle().map_err(|e| Error::Environment(format!("window: {e}")))?;
        // SAFETY: the window outlives the surface (Surface drops the swapchain first).
        let raw = unsafe {
            ash_window::create_surface(&instance.entry, &instance.raw, display.as_raw(), handle.as_raw(), None)
        }
        .vk("vkCreate*SurfaceKHR")?;
        let swapchain = match Swapchain::new(&self.device, raw, self.options.present) {
            Ok(swapchain) => swapchain,
            Err(e) => {
                // SAFETY: unused surface.
                unsafe { ash::khr::surface::Instance::new(&instance.entry, &instance.raw).destroy_surface(raw, None) };
                return Err(e);
            }
        };
        self.settings.color_format = swapchain.format;
        self.surface = Some(Surface { swapchain, depth: None, depth_used: false, window });
        self.recreate()?;
        self.build_renderer(self.options.scene.animation.clone())
    }

    /// (Re)create the swapchain and depth image at the window's size, without waiting for the
    /// queue: the old swapchain, its views and the old depth image are destroyed once the frames
    /// submitted before have finished, and its present semaphores once enough later frames have
    /// completed (`vk::swapchain::Retired`). A second re-creation while the first one's objects
    /// are still queued waits for the frame holding them (at most two swapchains exist).
    fn recreate(&mut self) -> Result<()> {
        if let Some(renderer) = self.renderer.as_mut() {
            renderer.flush_deletions()?;
        }
        let surface = self.surface.as_mut().expect("surface exists");
        let size = surface.window.inner_size();
        let old_depth = surface.depth.take();
        let (has_area, retired) =
            surface.swapchain.recreate(&self.device, vk::Extent2D { width: size.width, height: size.height })?;
        let (images, semaphores) = (retired.images() as u64, retired.split());
        let (old_images, old_semaphores) = semaphores;
        let in_flight = self.settings.frames_in_flight as u64;
        match self.renderer.as_mut() {
            Some(renderer) => {
                renderer.defer(Box::new(move |device| {
                    // SAFETY: the frames submitted before the re-creation have finished.
                    unsafe {
                        old_images.destroy(device);
                        if let Some(depth) = old_depth {
                            depth.destroy(device);
                        }
                    }
                }));
                // SAFETY (when run): presentations queued before were followed by `images +
                // in_flight` completed frames.
                renderer.defer_frames(
                    images + in_flight,
                    Box::new(move |device| unsafe { old_semaphores.destroy(device) }),
                );
            }
            None => {
                // No renderer: nothing was ever submitted with them.
                // SAFETY: unused.
                unsafe {
                    old_images.destroy(&self.device);
                    old_semaphores.destroy(&self.device);
                    if let Some(depth) = old_depth {
                        depth.destroy(&self.device);
                    }
                }
            }
        }
        self.minimised = !has_area;
        if has_area {
            let surface = self.surface.as_mut().expect("surface exists");
            let extent = surface.swapchain.extent;
            surface.depth = Some(Image::new(&self.device, &ImageDesc::depth("swapchain depth", DEPTH_FORMAT, extent))?);
            surface.depth_used = false;
        }
        self.needs_recreate = false;
        self.recreations += 1;
        Ok(())
    }

    /// Render one frame into the swapchain.
    fn render(&mut self) -> Result<()> {
        let inject = self.options.inject_out_of_date.is_some_and(|n| self.frames % u64::from(n) == u64::from(n) - 1);
        if self.needs_recreate || inject {
            self.recreate()?;
            if inject {
                // Count the injected frame so the injection does not repeat forever.
                self.frames += 1;
                return Ok(());
            }
            if self.minimised {
                return Ok(());
            }
        }
        // Allocated before the image is acquired: a failure must not strand an acquired image.
        let readback = match (&self.screenshot, &self.surface) {
            (Some(path), Some(surface)) if !surface.swapchain.screenshots => {
                return Err(Error::Environment(format!(
                    "screenshot {}: this surface's images cannot be copied (no TRANSFER_SRC usage)",
                    path.display()
                )));
            }
            (Some(_), Some(surface)) => {
                let e = surface.swapchain.extent;
                Some(Buffer::new(
                    &self.device,
                    &BufferDesc::readback(
                        "screenshot",
                        4 * u64::from(e.width) * u64::from(e.height),
                        vk::BufferUsageFlags::TRANSFER_DST,
                    ),
                )?)
            }
            _ => None,
        };
        let renderer = self.renderer.as_mut().expect("renderer built");
        let (slot, timings) = match renderer.begin_frame() {
            Ok(frame) => frame,
            Err(e) => {
                if let Some(buffer) = readback {
                    // SAFETY: never used by the GPU.
                    unsafe { buffer.destroy(&self.device) };
                }
                return Err(e);
            }
        };
        if let Some(t) = timings {
            self.stats.add(&t);
        }
        let surface = self.surface.as_mut().expect("surface exists");
        let acquired = surface.swapchain.acquire(renderer.acquire_semaphore(slot));
        let Ok(Some((index, suboptimal))) = acquired else {
            if let Some(buffer) = readback {
                // SAFETY: never used by the GPU.
                unsafe { buffer.destroy(&self.device) };
            }
            self.needs_recreate = true;
            return acquired.map(|_| ());
        };
        let extent = surface.swapchain.extent;
        let image = surface.swapchain.images[index as usize];
        let depth = surface.depth.as_ref().expect("depth exists with area");
        let view = TargetView {
            color: image,
            color_view: surface.swapchain.views[index as usize],
            depth: depth.raw,
            depth_view: depth.view,
            extent,
            color_previous: Access::Acquired,
            depth_previous: if surface.depth_used { Access::DepthAttachmentReadWrite } else { Access::Nothing },
        };
        surface.depth_used = true;
        let sync = crate::render::renderer::FrameSync {
            wait: Some(renderer.acquire_semaphore(slot)),
            signal: Some(surface.swapchain.present_semaphores[index as usize]),
        };
        let outputs = Outputs { readback: readback.as_ref().map(|b| b.raw), present: true };
        let submitted = renderer.submit_frame(slot, &view, &self.control.camera, self.time, sync, outputs);
        let result = submitted.and_then(|()| surface.swapchain.present(&self.device, index));
        if let (Some(buffer), Some(path)) = (readback, self.screenshot.take()) {
            // A screenshot is rare: wait for this frame, then write the picture.
            let written = renderer.wait_all_frames().and_then(|()| {
                let bgra = surface.swapchain.format == vk::Format::B8G8R8A8_UNORM;
                let rgba: Vec<u8> = if bgra {
                    buffer.mapped().chunks_exact(4).flat_map(|p| [p[2], p[1], p[0], p[3]]).collect()
                } else {
                    buffer.mapped().to_vec()
                };
                app::write_png(&path, (extent.width, extent.height), &rgba)
            });
            // SAFETY: the frame that wrote it completed.
            unsafe { buffer.destroy(&self.device) };
            written?;
            println!("screenshot: {} ({}x{})", path.display(), extent.width, extent.height);
        }
        if !result? || suboptimal {
            self.needs_recreate = true;
        }
        self.frames += 1;
        let (blades, terrain) = renderer.triangles();
        self.stats.tick(&surface.window, renderer.blade_count(), blades + terrain, &self.device.info.name);
        Ok(())
    }

    /// A named key went down or up (from the window or a script).
    fn key(&mut self, name: &str, pressed: bool) -> Result<()> {
        if self.control.key(name, pressed) || !pressed {
            return Ok(());
        }
        let renderer = self.renderer.as_mut().expect("renderer built");
        let wind = renderer.wind_mut();
        let mut rebuild = false;
        match name {
            "h" => println!("{HELP}"),
            "escape" => self.quit = true,
            "p" => self.paused = !self.paused,
            "g" => self.control.walk = !self.control.walk,
            "f12" => {
                self.screenshots_taken += 1;
                self.screenshot = Some(PathBuf::from(format!("meadow-screenshot-{}.png", self.screenshots_taken)));
            }
            "j" | "l" => {
                let global = wind.global.get_or_insert(crate::wind::GlobalWind {
                    direction_deg: 0.0,
                    strength: 0.3,
                    gusts: true,
                });
                global.direction_deg += if name == "j" { -15.0 } else { 15.0 };
                println!("wind direction {:.0} deg", global.direction_deg);
            }
            "i" | "k" => {
                let global = wind.global.get_or_insert(crate::wind::GlobalWind {
                    direction_deg: 0.0,
                    strength: 0.0,
                    gusts: true,
                });
                global.strength = (global.strength + if name == "i" { 0.05 } else { -0.05 }).max(0.0);
                println!("wind strength {:.2}", global.strength);
            }
            "u" => {
                if let Some(global) = wind.global.as_mut() {
                    global.gusts = !global.gusts;
                    println!("gusts {}", if global.gusts { "on" } else { "off" });
                }
            }
            "c" => match self.calm_off.take() {
                Some(calm) => wind.calm = calm,
                None => self.calm_off = Some(std::mem::take(&mut wind.calm)),
            },
            "delete" => {
                wind.sources.pop();
            }
            "up" | "down" | "left" | "right" => {
                if wind.colliders.is_empty() {
                    let p = self.control.camera.position + self.control.camera.forward() * 3.0;
                    let ground = self.scene.terrain.height_at(p.x, p.z);
                    wind.colliders
                        .push(Collider { center: Vec3::new(p.x, ground + 0.3, p.z), radii: Vec3::splat(0.3) });
                }
                let forward = self.control.camera.forward();
                let flat = Vec3::new(forward.x, 0.0, forward.z).normalize_or_zero();
                let step = match name {
                    "up" => flat,
                    "down" => -flat,
                    "right" => flat.cross(Vec3::Y),
                    _ => -flat.cross(Vec3::Y),
                } * 0.25;
                let c = wind.colliders.last_mut().expect("one collider");
                c.center += step;
                c.center.y = self.scene.terrain.height_at(c.center.x, c.center.z) + c.radii.y;
            }
            "m" | "n" | "b" | "v" | "f" | "plus" | "minus" | "[" | "]" => rebuild = true,
            _ => {}
        }
        if rebuild {
            self.rebuild_for(name)?;
        }
        Ok(())
    }

    /// Apply a control that changes pipelines or the scene, and rebuild the renderer. A change the
    /// device cannot take is reported and undone; the viewer carries on with what it had.
    fn rebuild_for(&mut self, name: &str) -> Result<()> {
        let renderer = self.renderer.as_ref().expect("renderer built");
        let old_animation = renderer.animation().clone();
        let old_settings = self.settings;
        let old_blades = self.scene.blades.len() as u32;
        let mut animation = old_animation.clone();
        let mut blades = old_blades;
        match name {
            "m" => {
                animation.mode = match animation.mode {
                    Mode::Static => Mode::Texture,
                    Mode::Texture => Mode::Uniform,
                    Mode::Uniform => Mode::Floor,
                    Mode::Floor => Mode::Static,
                }
            }
            "n" => {
                animation.smoothing = match animation.smoothing {
                    Smoothing::Nearest => Smoothing::Linear,
                    Smoothing::Linear => Smoothing::Slerp,
                    Smoothing::Slerp => Smoothing::Nearest,
                }
            }
            "b" => animation.eval = if animation.eval == Eval::Vertex { Eval::Blade } else { Eval::Vertex },
            "v" => self.settings.debug_force = !self.settings.debug_force,
            "f" => self.settings.wireframe = !self.settings.wireframe,
            "plus" => self.settings.segments = (self.settings.segments + 1).min(16),
            "minus" => self.settings.segments = self.settings.segments.saturating_sub(1).max(1),
            "[" => blades = (blades / 2).max(1),
            "]" => blades = blades.saturating_mul(2),
            _ => {}
        }
        // The old renderer's frames finish and its memory is freed before the new one is built.
        self.renderer = None;
        if blades != old_blades {
            self.scene = Scene::generate(blades, self.options.scene.seed);
        }
        if let Err(e) = self.build_renderer(animation) {
            println!("cannot apply '{name}': {e}");
            self.settings = old_settings;
            if blades != old_blades {
                self.scene = Scene::generate(old_blades, self.options.scene.seed);
            }
            return self.build_renderer(old_animation);
        }
        let a = self.renderer.as_ref().expect("built").animation();
        println!(
            "mode {:?}, smoothing {:?}, eval {:?}, {} segments, {} blades{}{}",
            a.mode,
            a.smoothing,
            a.eval,
            self.settings.segments,
            self.scene.blades.len(),
            if self.settings.debug_force { ", force view" } else { "" },
            if self.settings.wireframe { ", wireframe" } else { "" },
        );
        Ok(())
    }

    /// Left click at a pixel: drop a wind source where the ray hits the terrain.
    fn click(&mut self, x: f64, y: f64) {
        if let Some(hit) = self.pick(x, y) {
            let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
            if wind.sources.len() + wind.colliders.len() >= crate::render::animation::MAX_EMITTERS {
                println!("at most {} sources and colliders", crate::render::animation::MAX_EMITTERS);
                return;
            }
            wind.sources.push(PointSource { position: hit, power: 0.12, sigma: 2.0, velocity: Vec2::ZERO });
            self.dragging = true;
            println!("wind source at {:.1}, {:.1}", hit.x, hit.y);
        }
    }

    /// The terrain point under a pixel, marching the view ray.
    fn pick(&self, x: f64, y: f64) -> Option<Vec2> {
        let extent = self.surface.as_ref()?.swapchain.extent;
        let ndc = Vec2::new(
            (2.0 * x / f64::from(extent.width) - 1.0) as f32,
            (2.0 * y / f64::from(extent.height) - 1.0) as f32,
        );
        let inverse = self.control.camera.view_projection(extent.width as f32 / extent.height as f32).inverse();
        let unproject = |z: f32| {
            let p = inverse * Vec4::new(ndc.x, ndc.y, z, 1.0);
            p.truncate() / p.w
        };
        let (near, mid) = (unproject(1.0), unproject(0.5));
        let direction = (mid - near).normalize();
        let mut p = near;
        for _ in 0..4000 {
            p += direction * 0.05;
            if p.y <= self.scene.terrain.height_at(p.x, p.z) {
                return Some(Vec2::new(p.x, p.z));
            }
        }
        None
    }

    /// One loop iteration: script actions, camera, and a frame unless minimised.
    fn tick(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        for action in self.script.due(self.tick) {
            self.act(action)?;
        }
        self.tick += 1;
        let now = Instant::now();
        let dt = if self.fixed_step { 1.0 / 60.0 } else { (now - self.last_tick).as_secs_f32().min(0.1) };
        self.last_tick = now;
        self.control.update(dt, &self.scene.terrain);
        if !self.paused {
            self.time += dt;
        }
        let surface = self.surface.as_ref().expect("surface exists");
        let size = surface.window.inner_size();
        let minimised = size.width == 0 || size.height == 0 || surface.window.is_minimized() == Some(true);
        if minimised {
            // Nothing to draw into: sleep until an event or the next script tick, no busy loop.
            self.minimised = true;
            event_loop.set_control_flow(ControlFlow::WaitUntil(now + Duration::from_millis(50)));
            return Ok(());
        }
        if self.minimised {
            self.minimised = false;
            self.needs_recreate = true;
        }
        event_loop.set_control_flow(ControlFlow::Poll);
        self.render()?;
        if self.options.frames.is_some_and(|n| self.frames >= n)
            || (self.options.script.is_some() && self.script.is_empty() && self.options.frames.is_none())
        {
            self.quit = true;
        }
        Ok(())
    }

    fn act(&mut self, action: Action) -> Result<()> {
        let window = &self.surface.as_ref().expect("surface exists").window;
        match action {
            Action::Camera(camera) => self.control.camera = camera,
            Action::Time(t) => self.time = t,
            Action::Pause => self.paused = !self.paused,
            Action::Key(name, pressed) => self.key(&name, pressed)?,
            Action::Press(name) => {
                self.key(&name, true)?;
                self.key(&name, false)?;
            }
            Action::Click(x, y) => {
                self.click(x, y);
                self.dragging = false;
            }
            Action::Resize(w, h) => {
                let _ = window.request_inner_size(PhysicalSize::new(w, h));
                self.needs_recreate = true;
            }
            Action::Minimise => window.set_minimized(true),
            Action::Restore => {
                window.set_minimized(false);
                self.needs_recreate = true;
            }
            Action::Screenshot(path) => self.screenshot = Some(PathBuf::from(path)),
            Action::Quit => self.quit = true,
        }
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

/// Name of a key as the help and scripts spell it.
fn key_name(code: KeyCode) -> Option<&'static str> {
    Some(match code {
        KeyCode::KeyW => "w",
        KeyCode::KeyA => "a",
        KeyCode::KeyS => "s",
        KeyCode::KeyD => "d",
        KeyCode::KeyQ => "q",
        KeyCode::KeyE => "e",
        KeyCode::ShiftLeft | KeyCode::ShiftRight => "shift",
        KeyCode::KeyG => "g",
        KeyCode::KeyH => "h",
        KeyCode::KeyM => "m",
        KeyCode::KeyN => "n",
        KeyCode::KeyB => "b",
        KeyCode::Equal | KeyCode::NumpadAdd => "plus",
        KeyCode::Minus | KeyCode::NumpadSubtract => "minus",
        KeyCode::BracketLeft => "[",
        KeyCode::BracketRight => "]",
        KeyCode::KeyJ => "j",
        KeyCode::KeyL => "l",
        KeyCode::KeyI => "i",
        KeyCode::KeyK => "k",
        KeyCode::KeyU => "u",
        KeyCode::KeyC => "c",
        KeyCode::KeyV => "v",
        KeyCode::KeyF => "f",
        KeyCode::KeyP => "p",
        KeyCode::F12 => "f12",
        KeyCode::Delete | KeyCode::Backspace => "delete",
        KeyCode::ArrowUp => "up",
        KeyCode::ArrowDown => "down",
        KeyCode::ArrowLeft => "left",
        KeyCode::ArrowRight => "right",
        KeyCode::Escape => "escape",
        _ => return None,
    })
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.surface.is_none() {
            println!("{HELP}");
            if let Err(e) = self.create_surface(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let result = match event {
            WindowEvent::CloseRequested => {
                self.quit = true;
                Ok(())
            }
            WindowEvent::Resized(_) => {
                self.needs_recreate = true;
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } => match (event.physical_key, event.repeat) {
                (PhysicalKey::Code(code), false) => match key_name(code) {
                    Some(name) => self.key(name, event.state == ElementState::Pressed),
                    None => Ok(()),
                },
                _ => Ok(()),
            },
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                self.control.cursor(position.x, position.y);
                if self.dragging {
                    if let Some(hit) = self.pick(position.x, position.y) {
                        if let Some(source) = self.renderer.as_mut().and_then(|r| r.wind_mut().sources.last_mut()) {
                            source.position = hit;
                        }
                    }
                }
                Ok(())
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                match button {
                    MouseButton::Right => self.control.look_button(pressed),
                    MouseButton::Left if pressed => self.click(self.cursor.0, self.cursor.1),
                    MouseButton::Left => self.dragging = false,
                    _ => {}
                }
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.control.wheel(steps);
                Ok(())
            }
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.surface.is_none() || self.error.is_some() {
            return;
        }
        if INTERRUPTED.load(Ordering::SeqCst) {
            self.quit = true;
        }
        if !self.quit {
            if let Err(e) = self.tick(event_loop) {
                self.fail(event_loop, e);
                return;
            }
        }
        if self.quit {
            if let Some(path) = self.options.screenshot.take() {
                // The exit screenshot: one more frame, written to the file.
                self.screenshot = Some(path.clone());
                let rendered = self.render().and_then(|()| match self.screenshot {
                    Some(_) => Err(Error::Environment(format!(
                        "--screenshot {}: the window has no area (minimised), nothing to capture",
                        path.display()
                    ))),
                    None => Ok(()),
                });
                if let Err(e) = rendered {
                    self.fail(event_loop, e);
                    return;
                }
            }
            event_loop.exit();
        }
    }
}
