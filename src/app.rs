//! The commands behind the CLI: `render`, `devices` and `keyframes` ([`keyframes`]), and what the
//! other tools share: opening a device ([`with_device`]), the limit and scene checks (`limits`), writing PNG
//! and text files atomically, and the parsers of the values the command line and the viewer's
//! scripts take ([`values`]). [`crate::cli`] parses arguments into these options and prints what
//! they return.

mod host_heap;
pub mod input;
pub mod interrupt;
mod keyframe_report;
pub mod landscape;
mod limits;
pub mod output;
pub mod values;

pub use keyframe_report::{keyframes, KeyframeOptions};
pub use limits::{check_limits, check_scene, check_timestamps_for_budget, frame_target_bytes, MAX_CORNERS};

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::error::{Error, Result};
use crate::render::animation::AnimationSettings;
use crate::render::budget::FrameBudget;
use crate::render::submission::Submission;
use crate::render::{FrameTimings, OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{blades, Scene};
use crate::vk::device::DeviceInfo;
use crate::vk::{Device, DeviceDesc, DeviceSelector, Instance, InstanceDesc};

/// Options every GPU command takes.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Khronos validation with synchronization validation.
    pub validation: bool,
    /// Which device.
    pub device: DeviceSelector,
}

/// Run `body` with a device, then tear everything down and count validation messages.
///
/// Returns the body's result and, with validation on, the number of warnings and errors the
/// layers reported — including those emitted during teardown (leaks).
pub fn with_device<T>(
    options: &GpuOptions,
    swapchain: bool,
    body: impl FnOnce(&Arc<Device>) -> Result<T>,
) -> (Result<T>, Option<u64>) {
    with_device_extensions(options, &[], swapchain, body)
}

/// [`with_device`] with extra instance extensions (a window's surface extensions).
pub fn with_device_extensions<T>(
    options: &GpuOptions,
    extensions: &[*const std::ffi::c_char],
    swapchain: bool,
    body: impl FnOnce(&Arc<Device>) -> Result<T>,
) -> (Result<T>, Option<u64>) {
    with_instance(options, extensions, |instance| {
        let desc = DeviceDesc { selector: options.device.clone(), swapchain, surface: None };
        Device::new(instance, &desc).and_then(|device| body(&device))
    })
}

/// Run `body` with an instance (it makes the device itself: the viewer chooses one that can
/// present to its window), then count validation messages once everything is gone.
pub fn with_instance<T>(
    options: &GpuOptions,
    extensions: &[*const std::ffi::c_char],
    body: impl FnOnce(Arc<Instance>) -> Result<T>,
) -> (Result<T>, Option<u64>) {
    // Before the driver allocates: a software device's per-frame scene memory is reused instead
    // of faulted in again each frame.
    host_heap::keep_freed_memory();
    let instance = match Instance::create(&InstanceDesc { validation: options.validation, extensions }) {
        Ok(instance) => Arc::new(instance),
        // The loader's messages about a missing driver are counted too.
        Err((e, messages)) => return (Err(e), messages),
    };
    let counter = instance.validation_counter();
    let result = body(instance);
    // Every Arc<Device> and Arc<Instance> is gone here: teardown messages are counted.
    (result, counter.map(|c| c.count()))
}

/// List the physical devices.
pub fn devices(options: &GpuOptions) -> (Result<(Vec<DeviceInfo>, bool)>, Option<u64>) {
    let instance = match Instance::create(&InstanceDesc { validation: options.validation, extensions: &[] }) {
        Ok(instance) => instance,
        Err((e, messages)) => return (Err(e), messages),
    };
    let counter = instance.validation_counter();
    let portability = instance.portability_enumeration;
    let result = crate::vk::device::list_devices(&instance).map(|devices| (devices, portability));
    drop(instance);
    (result, counter.map(|c| c.count()))
}

/// `meadow render` options, validated by the CLI parsers.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Blade count.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Picture size.
    pub size: (u32, u32),
    /// Scene seed.
    pub seed: u64,
    /// Camera, or a preset placed on the scene (`Scene::camera`); `None` for the default view.
    pub camera: Option<crate::scene::CameraChoice>,
    /// Output PNG.
    pub out: PathBuf,
    /// Frames to render (the last is written; more than one gives warm timings).
    pub frames: u32,
    /// Blades per instance of the blade draw.
    pub blades_per_instance: u32,
    /// How blades are animated and by what.
    pub animation: AnimationSettings,
    /// Simulation time of the picture (seconds).
    pub time: f32,
    /// Colour blades by force magnitude.
    pub debug_force: bool,
    /// Draw the force clusters' edges over the picture.
    pub debug_bounds: bool,
    /// Draw the wind field as arrows on a slice above the ground.
    pub debug_wind: bool,
    /// Colour blades by LOD bucket.
    pub debug_lod: bool,
    /// Colour blades by tile.
    pub debug_tiles: bool,
    /// Show the Fresnel term alone on the blades.
    pub debug_fresnel: bool,
    /// Show the ground's cover as colour.
    pub debug_cover: bool,
    /// Show the pressed map's bend and cut as colour.
    pub debug_pressed: bool,
    /// Show the interaction patches as colour.
    pub debug_patches: bool,
    /// Show the far field apart from the blades.
    pub debug_far: bool,
    /// Multisample anti-aliasing.
    pub msaa: crate::render::msaa::Msaa,
    /// The cull and LOD, or brute force.
    pub culling: crate::render::culling::Culling,
    /// Frame-time budget in milliseconds: the LOD scale follows the measured GPU time.
    pub budget_ms: Option<f32>,
    /// A field of camera-following blocks instead of `blades` stored blades.
    pub field: Option<crate::scene::field::FieldSpec>,
    /// The relief under a block field.
    pub relief: crate::scene::field::ReliefKind,
    /// `--heightmap`, `--terrain-scale`, `--cover` and `--slope-limit`: the ground and where
    /// grass grows on it, loaded by `scene`.
    pub landscape: landscape::Landscape,
    /// `--clumps`: blades in clumps.
    pub clumps: Option<crate::scene::clumps::Clumps>,
    /// `--flowers`: flowers among the blades.
    pub flowers: Option<crate::scene::flowers::Flowers>,
    /// Fog density per metre.
    pub fog: f32,
    /// Draw the benchmark floor instead of the blades (`--mode floor`).
    pub floor: bool,
    /// How the blade draws are submitted.
    pub submission: crate::render::submission::Submission,
}

impl RenderOptions {
    /// The blades the renderer stores: `--blades`, or a block field's block.
    pub fn stored_blades(&self) -> u32 {
        self.field.map_or(self.blades, |f| f.block_blades() as u32)
    }

    /// The scene: stored blades or a block field, on the procedural ground or on the
    /// `--heightmap`, under the cover rules (`landscape`; the maps are loaded here, and a bad map
    /// is bad input, refused in one line).
    pub fn scene(&self) -> Result<Scene> {
        // Flowers denser than the blades are refused before any map is read.
        let density = self.field.map_or(crate::scene::blades::DENSITY_PER_M2, |f| f.density);
        if let Some(flowers) = self.flowers {
            flowers.share(density)?;
        }
        let scene = self.grass()?;
        match self.flowers {
            Some(flowers) => scene.with_flowers(flowers),
            None => Ok(scene),
        }
    }

    /// The ground's and the plants' options as a line's tail (`render`'s scene line, the viewer's
    /// rebuild line): ", heightmap, cover map, slope limit 30°, clumps of 1.5 m, 20 flowers per
    /// m²", each only when given.
    pub fn landscape_summary(&self) -> String {
        let l = &self.landscape;
        [
            l.heightmap.as_ref().map(|_| "heightmap".to_string()),
            l.cover.as_ref().map(|_| "cover map".to_string()),
            l.slope_limit_deg.map(|d| format!("slope limit {d}°")),
            self.clumps.map(|c| format!("clumps of {} m", c.size_m)),
            self.flowers.map(|f| format!("{} flowers per m²", f.per_m2)),
        ]
        .into_iter()
        .flatten()
        .map(|part| format!(", {part}"))
        .collect()
    }

    /// `scene`'s ground and grass, before the flowers.
    fn grass(&self) -> Result<Scene> {
        let heightmap = self.landscape.heightmap(self.field)?;
        let cover = self.landscape.cover(self.field)?;
        let Some(spec) = self.field else {
            // Stored blades: scattered once, under the cover rules and in clumps.
            let size = crate::scene::blades::field_size(self.blades);
            let terrain = match &heightmap {
                Some(map) => crate::scene::Terrain::from_heightmap(size, map),
                None => crate::scene::Terrain::generate(size, self.seed),
            };
            return Ok(Scene::stored_on(terrain, self.blades, self.seed, (cover, self.clumps)));
        };
        let scene = match heightmap {
            None => Scene::blocks_on(spec, self.relief, self.seed),
            Some(map) => Scene::blocks_on_map(spec, std::sync::Arc::new(map), self.seed),
        };
        let scene = Scene { cover, ..scene };
        Ok(match self.clumps {
            Some(clumps) => scene.with_clumps(clumps),
            None => scene,
        })
    }

    /// Refuse more clusters than blades, for the strategies that split the blades into clusters
    /// (`--clusters` means nothing to the instanced and pre-recorded draws, so its default never
    /// refuses a small field).
    pub fn check_clusters(&self) -> Result<()> {
        use crate::render::submission::Strategy;
        let Submission { strategy, clusters } = self.submission;
        if matches!(strategy, Strategy::Instanced | Strategy::Prerecorded) || clusters <= self.stored_blades() {
            return Ok(());
        }
        // Name the strategy too: `--clusters` may not have been given (its default is 64).
        Err(Error::bad_input(format!(
            "--clusters {clusters} exceeds --blades {}: a cluster holds a blade at least (--submission {} splits \
             the blades into --clusters clusters, 64 unless given)",
            self.stored_blades(),
            strategy.name()
        )))
    }

    /// Refuse what a block field cannot do, before any work (`render::settings::check_field`),
    /// and a `--camera` past the distance it is drawn within (`scene::field::MAX_DISTANCE`).
    pub fn check_field(&self) -> Result<()> {
        if self.field.is_none() {
            return Ok(());
        }
        if let Some(crate::scene::CameraChoice::At(camera)) = &self.camera {
            crate::scene::field::check_camera(camera.position)
                .map_err(|e| Error::bad_input(format!("--camera: {e}")))?;
        }
        crate::render::settings::check_field(&self.offscreen_settings(1))
    }

    /// The renderer settings of these options for offscreen targets with pipeline statistics
    /// (`render`, `timing`; the viewer changes the format and drops the statistics).
    pub fn offscreen_settings(&self, frames_in_flight: usize) -> RenderSettings {
        RenderSettings {
            frames_in_flight,
            blades_per_instance: self.blades_per_instance,
            debug_force: self.debug_force,
            debug_bounds: self.debug_bounds,
            debug_wind: self.debug_wind,
            debug_lod: self.debug_lod,
            debug_tiles: self.debug_tiles,
            debug_fresnel: self.debug_fresnel,
            debug_cover: self.debug_cover,
            debug_pressed: self.debug_pressed,
            debug_patches: self.debug_patches,
            debug_far: self.debug_far,
            msaa: self.msaa,
            floor: self.floor,
            fog_density: self.fog,
            pipeline_statistics: true,
            submission: self.submission,
            ..RenderSettings::offscreen(self.segments, self.culling)
        }
    }
}

/// What `meadow render` did.
#[derive(Clone, Debug)]
pub struct RenderReport {
    /// The device used.
    pub device: DeviceInfo,
    /// Blades drawn.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Field side in metres.
    pub field_m: f32,
    /// Triangles (blades, terrain).
    pub triangles: (u64, u64),
    /// Timings of every frame rendered.
    pub frames: Vec<FrameTimings>,
    /// CPU time to build and upload the scene and pipelines.
    pub setup_ms: f64,
    /// Picture written.
    pub out: PathBuf,
    /// Its size.
    pub size: (u32, u32),
    /// `--budget-ms`: the budget and the LOD scale the last frame was rendered at.
    pub budget: Option<(f32, f32)>,
    /// A block field's size and density (`None`: `blades` stored blades).
    pub field: Option<crate::scene::field::FieldSpec>,
    /// What the device made the renderer do differently from the options (a fallback).
    pub notes: Vec<String>,
    /// The simulated time of the picture and the fixed step its frames lie apart
    /// (`render::animation::clock`).
    pub clock: (f32, crate::render::animation::clock::StepClock),
    /// Warm-up steps before the frames (`warm_up`), and whether the response keeps state.
    pub warm_up: (u64, bool),
    /// How the renderer submitted the blades: its strategy and clusters, and the blades per
    /// instance of its draws (what `--submission`, `--clusters` and `--blades-per-instance`
    /// chose, as the renderer was built).
    pub submission: (crate::render::submission::Submission, u32),
    /// The ground's and the plants' options (`RenderOptions::landscape_summary`).
    pub landscape: String,
    /// With colliders, the blades the last frame listed for the interaction patches and those
    /// holding a patch.
    pub patches: Option<(u64, u64)>,
    /// With a far field, what the last frame drew of it.
    pub far: Option<crate::render::far_field::FarCounts>,
}

/// With colliders, the interaction patches after the last frame, which drew `step` (issue #34: how
/// many blades hold state): the blades listed, and those holding a patch.
pub(crate) fn patch_counts(renderer: &Renderer, step: u64) -> Result<Option<(u64, u64)>> {
    match renderer.animation().wind.colliders.is_empty() {
        true => Ok(None),
        false => renderer.patch_counts(step),
    }
}

/// One line per setting the device made the renderer change (`Renderer::new`'s fallbacks).
fn fallback_notes(device: &Device, asked: &AnimationSettings, used: &AnimationSettings) -> Vec<String> {
    use crate::render::animation::keyframe_gpu::texture_format;
    let mut notes = Vec::new();
    let preferred = crate::vk::device::DEPTH_FORMATS[0];
    if device.depth_format != preferred {
        notes.push(format!(
            "{} cannot attach and sample {preferred:?}: depth in {:?} instead",
            device.info.name, device.depth_format
        ));
    }
    if asked.mode == crate::render::animation::Mode::Texture && asked.encoding != used.encoding {
        notes.push(format!(
            "{} cannot sample {:?}: keyframes encoded {:?} instead",
            device.info.name,
            texture_format(asked.encoding),
            used.encoding
        ));
    }
    notes
}

/// Write an RGBA8 readback as an RGB PNG, whole or not at all (`output::write_atomically`).
pub fn write_png(path: &Path, size: (u32, u32), rgba: &[u8]) -> Result<()> {
    let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let image = image::RgbImage::from_raw(size.0, size.1, rgb).expect("readback holds width*height pixels");
    output::write_atomically(path, &output::encode_png(&image)?)
}

/// `meadow render`: build the scene, render it headless, write the PNG.
pub fn render(device: &Arc<Device>, options: &RenderOptions) -> Result<RenderReport> {
    output::check_output(&options.out, "--out")?;
    options.check_field()?;
    let culled = options.culling.enabled;
    check_scene(
        device,
        options.stored_blades(),
        options.segments,
        options.size,
        &options.animation,
        options.floor,
        (culled, options.msaa, options.offscreen_settings(1).linear_scene()),
    )?;
    options.check_clusters()?;
    check_timestamps_for_budget(device, options.budget_ms)?;
    let field_m = blades::field_size(options.blades);

    let setup = Instant::now();
    let scene = options.scene()?;
    let camera = scene.camera(options.camera);
    let mut renderer = Renderer::new(device.clone(), &scene, options.offscreen_settings(1), options.animation.clone())?;
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let mut target = OffscreenTarget::new(device, extent)?;
    let setup_ms = setup.elapsed().as_secs_f64() * 1e3;

    let mut budget = options.budget_ms.map(|ms| FrameBudget::new(ms, options.culling.lod_scale));
    // The scale the last frame was rendered at.
    let mut frames_scale = None;
    let result = (|| {
        let mut frames = Vec::new();
        // One step a frame, the last at --time: the picture written does not depend on --frames.
        let clock = options.animation.clock;
        let first = clock.step_before(options.time.into(), options.frames - 1);
        let warm_up = warm_up(&mut renderer, &mut target, &camera, first)?;
        for i in 0..options.frames {
            interrupt::check()?;
            let step = clock.step_before(options.time.into(), options.frames - 1 - i);
            let time = clock.time_of(step) as f32;
            let timings = renderer.render_offscreen(&mut target, &camera, time)?;
            if let Some(budget) = budget.as_mut() {
                frames_scale = Some(budget.scale);
                renderer.set_lod_scale(budget.update(timings.gpu_ms));
            }
            frames.push(timings);
        }
        write_png(&options.out, options.size, target.pixels())?;
        let patches = patch_counts(&renderer, clock.steps_to(options.time.into()))?;
        Ok((frames, warm_up, (patches, renderer.far_counts()?)))
    })();
    let stateful = renderer.stateful();
    let triangles = renderer.triangles();
    let notes = fallback_notes(device, &options.animation, renderer.animation());
    let submission = (renderer.settings().submission, renderer.settings().blades_per_instance);
    drop(renderer);
    // SAFETY: render_offscreen waited for its fence; nothing else uses the target.
    unsafe { target.destroy(device) };
    let (frames, warm_up, (patches, far)) = result?;
    Ok(RenderReport {
        device: device.info.clone(),
        blades: options.blades,
        segments: options.segments,
        field_m,
        triangles,
        frames,
        warm_up: (warm_up, stateful),
        setup_ms,
        out: options.out.clone(),
        size: options.size,
        budget: options.budget_ms.zip(frames_scale),
        field: options.field,
        notes,
        submission,
        clock: (options.time, options.animation.clock),
        landscape: options.landscape_summary(),
        patches,
        far,
    })
}

/// Bring a stateful response to the step before `first`: one frame per step from step 0 (the
/// equilibrium under the wind at t = 0; with only interaction patches keeping state, from
/// `Renderer::warm_up_from`'s step), as the headless commands advance, so the state at `first`
/// does not depend on how many frames follow. Returns the steps taken: 0 for a stateless
/// response, which draws any step as it is.
pub fn warm_up(
    renderer: &mut Renderer,
    target: &mut OffscreenTarget,
    camera: &crate::scene::Camera,
    first: u64,
) -> Result<u64> {
    let Some(start) = renderer.warm_up_from(first) else {
        return Ok(0);
    };
    let clock = renderer.animation().clock;
    for step in start..first {
        interrupt::check()?;
        renderer.render_offscreen(target, camera, clock.time_of(step) as f32)?;
    }
    Ok(first - start)
}

/// Median of a slice (empty → 0).
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let mid = values.len() / 2;
    if values.len().is_multiple_of(2) {
        0.5 * (values[mid - 1] + values[mid])
    } else {
        values[mid]
    }
}

/// Write a text file whole or not at all (`output::write_atomically`).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    output::write_atomically(path, text.as_bytes())
}
