//! How a renderer is built (`RenderSettings`, the ranges the CLI checks against), and the checks
//! and derived values of the settings that do not need a renderer.

use ash::vk;

use crate::error::{Error, Result};
use crate::render::frame::look;
use crate::render::submission::{Strategy, Submission};
use crate::vk::Device;

pub use crate::render::limits::{BLADES_PER_INSTANCE_RANGE, SEGMENTS_RANGE};

/// How the renderer is built.
#[derive(Clone, Copy, Debug)]
pub struct RenderSettings {
    /// Quads per blade.
    pub segments: u32,
    /// Colour attachment format of the targets.
    pub color_format: vk::Format,
    /// Whether the shaders encode sRGB (UNORM targets) or the format does (`*_SRGB`).
    pub encode_srgb: bool,
    /// Frames in flight (1 for headless rendering).
    pub frames_in_flight: usize,
    /// Blades drawn per instance of the blade draw (see `BladePass::record`).
    pub blades_per_instance: u32,
    /// Colour blades by the magnitude of their force (thesis fig. 4.5 / 6.1c).
    pub debug_force: bool,
    /// Draw triangle edges only (needs `fillModeNonSolid`).
    pub wireframe: bool,
    /// Count pipeline statistics per pass (when the device has `pipelineStatisticsQuery`).
    pub pipeline_statistics: bool,
    /// How the blade pass submits its draws (`meadow overhead`); the floor ignores it.
    pub submission: Submission,
    /// Draw the cluster grid over the picture (`--debug-view bounds`).
    pub debug_bounds: bool,
    /// Draw the wind field as arrows on a slice above the ground (`--debug-view wind`).
    pub debug_wind: bool,
    /// Colour blades by their LOD bucket (`--debug-view lod`).
    pub debug_lod: bool,
    /// Colour blades by their tile (`--debug-view tiles`).
    pub debug_tiles: bool,
    /// Show Belyaev's Fresnel term alone on the blades (`--debug-view fresnel`).
    pub debug_fresnel: bool,
    /// The ground's cover as colour on the terrain and the blades (`--debug-view cover`).
    pub debug_cover: bool,
    /// The pressed map's bend and cut as colour on the blades (`--debug-view pressed`).
    pub debug_pressed: bool,
    /// The interaction patches' chains' share as colour on the blades (`--debug-view patches`).
    pub debug_patches: bool,
    /// The far field apart from the blades and their band as colour (`--debug-view far`).
    pub debug_far: bool,
    /// The GPU-driven cull and LOD, or brute force.
    pub culling: crate::render::culling::Culling,
    /// Multisample anti-aliasing (`--msaa`, `render::msaa`).
    pub msaa: crate::render::msaa::Msaa,
    /// Draw the benchmark floor instead of the blades: the static blades' triangles pre-expanded
    /// on the CPU, transform and flat colour only (`--mode floor`; a reference pass, not an
    /// animation).
    pub floor: bool,
    /// The fog's density per metre (`--fog`; `look::FOG_DENSITY` by default, 0: no fog).
    pub fog_density: f32,
}

impl RenderSettings {
    /// Into offscreen targets (`render::target::OFFSCREEN_FORMAT`), one frame in flight, the
    /// default blades per instance (`default_blades_per_instance`), instanced, no debug view, no statistics, blades (not the floor), with
    /// `culling`: the base the harnesses and tests change a field or two of.
    pub fn offscreen(segments: u32, culling: crate::render::culling::Culling) -> Self {
        Self {
            segments,
            color_format: crate::render::target::OFFSCREEN_FORMAT,
            encode_srgb: true,
            frames_in_flight: 1,
            blades_per_instance: default_blades_per_instance(culling.enabled),
            debug_force: false,
            wireframe: false,
            pipeline_statistics: false,
            submission: Submission::default(),
            debug_bounds: false,
            debug_wind: false,
            debug_lod: false,
            debug_tiles: false,
            debug_fresnel: false,
            debug_cover: false,
            debug_pressed: false,
            debug_patches: false,
            debug_far: false,
            culling,
            msaa: crate::render::msaa::Msaa::default(),
            floor: false,
            fog_density: look::FOG_DENSITY,
        }
    }
}

impl RenderSettings {
    /// Whether the scene passes draw in linear light into an RGBA16F intermediate that the
    /// resolve pass encodes into the target (`render::msaa`): with `--msaa`, and with the far
    /// field blended (`--fade blend`: blending the UNORM target's encoded values would mix them
    /// in the wrong space).
    pub fn linear_scene(&self) -> bool {
        self.msaa.enabled() || (!self.floor && self.culling.blends_far_field())
    }
}

/// Default blades per instance without the cull: one (classic instancing, the thesis' path).
pub const DEFAULT_BLADES_PER_INSTANCE: u32 = 1;
/// Default blades per instance of the cull's indirect draws: 32 entries of the visible list per
/// instance (strips joined by degenerate triangles). lavapipe's vertex stage pays a fixed cost
/// per instance; at 1M blades, default camera, 32 took the frame from 163 to 159 ms and an
/// unbounded field from 228 to 211 ms (`meadow bench --preset lod`, one run each).
pub const DEFAULT_CULLED_BLADES_PER_INSTANCE: u32 = 32;

/// Blades per instance unless `--blades-per-instance` says otherwise.
pub fn default_blades_per_instance(culled: bool) -> u32 {
    if culled {
        DEFAULT_CULLED_BLADES_PER_INSTANCE
    } else {
        DEFAULT_BLADES_PER_INSTANCE
    }
}

/// The clear colour of the sky as the target stores it.
pub(crate) fn sky_clear_color(encode_srgb: bool) -> [f32; 4] {
    let sky = look::SKY;
    if encode_srgb {
        [look::encode_srgb(sky.x), look::encode_srgb(sky.y), look::encode_srgb(sky.z), 1.0]
    } else {
        [sky.x, sky.y, sky.z, 1.0]
    }
}

/// FILL, or LINE for wireframes when the device can.
pub(crate) fn polygon_mode(device: &Device, wireframe: bool) -> Result<vk::PolygonMode> {
    if !wireframe {
        return Ok(vk::PolygonMode::FILL);
    }
    if device.features.fill_mode_non_solid == vk::FALSE {
        return Err(Error::Environment(format!("{} cannot draw wireframes (no fillModeNonSolid)", device.info.name)));
    }
    Ok(vk::PolygonMode::LINE)
}

/// Refuse a submission strategy the device cannot run, or combined with blades per instance.
pub(crate) fn check_submission(device: &Device, settings: &RenderSettings) -> Result<()> {
    let Submission { strategy, clusters } = settings.submission;
    if settings.culling.enabled && !settings.floor {
        settings.culling.rows.check(device)?;
        if strategy != Strategy::Instanced {
            return Err(Error::bad_input(format!(
                "--submission {} draws every stored blade: add --brute-force",
                strategy.name()
            )));
        }
        if settings.culling.lod_segments.counts()[0] > settings.segments {
            return Err(Error::bad_input(format!(
                "--lod-segments starts at {}, over --segments {}",
                settings.culling.lod_segments.counts()[0],
                settings.segments
            )));
        }
        if device.features.draw_indirect_first_instance == vk::FALSE {
            return Err(Error::Environment(format!(
                "{} cannot draw the culled blades (no drawIndirectFirstInstance): use --brute-force",
                device.info.name
            )));
        }
    }
    if strategy == Strategy::Instanced || settings.floor {
        return Ok(());
    }
    if let Some(why) = strategy.unsupported(device, clusters) {
        return Err(Error::Environment(format!("{} cannot submit `{}`: {why}", device.info.name, strategy.name())));
    }
    if settings.blades_per_instance != 1 {
        return Err(Error::bad_input("submission strategies draw one blade per instance: drop --blades-per-instance"));
    }
    Ok(())
}

/// Refuse `--eval blade` with brute force when the pose records (`scene_gpu::pose_records`, one
/// storage buffer's worth) cannot hold one per blade; the cull needs one per drawn blade only.
/// `culled`, `floor`: the draw path (the floor reads no records).
pub fn check_pose_records(
    device: &Device,
    animation: &crate::render::animation::AnimationSettings,
    (blades, segments): (u32, u32),
    culled: bool,
    floor: bool,
) -> Result<()> {
    let most = crate::render::scene_gpu::most_pose_records(device, segments);
    let Some(writer) = animation.pose_writer() else {
        return Ok(());
    };
    if !culled && !floor && u64::from(blades) > most {
        let bytes = crate::render::scene_gpu::pose_bytes(blades, segments);
        let instead = match writer {
            "--eval blade" => "use --eval vertex or the cull",
            _ => "use the cull",
        };
        return Err(Error::bad_input(format!(
            "{writer} with --brute-force and {blades} blades x {segments} segments needs {} MiB of evaluated levels, over the device's maxStorageBufferRange of {} MiB: {instead}",
            bytes >> 20,
            device.limits().max_storage_buffer_range >> 20
        )));
    }
    Ok(())
}

/// Refuse, for a block field (`--field`), what it cannot do: it is drawn only through the cull
/// (its blades are placed per cell by the cull and the blade shader).
pub fn check_field(settings: &RenderSettings) -> Result<()> {
    let refuse = |what: &str| Err(Error::bad_input(format!("--field {what}")));
    if !settings.culling.enabled {
        return refuse("is drawn through the cull: drop --brute-force");
    }
    if settings.floor {
        return refuse("has no floor reference: drop --mode floor");
    }
    if settings.debug_bounds {
        return refuse("has no fixed cluster grid to draw: drop --debug-view bounds");
    }
    if let Some(rings) = settings.culling.far_rings() {
        let reach = crate::render::far_rings::FarRings::reach(rings.blade_range);
        if rings.view_distance > reach {
            return Err(Error::bad_input(format!(
                "--view-distance {} is past the far field's reach from a blade distance of {} m: its {} rings end at {:.0} m (give a blade distance of {:.2} m or more, a shorter view, or --far-field off)",
                rings.view_distance,
                rings.blade_range,
                crate::render::far_rings::MAX_RINGS,
                reach,
                rings.blade_range * rings.view_distance / reach
            )));
        }
    }
    let most = crate::render::field_gpu::max_blade_distance();
    if settings.culling.blade_range() > most {
        return refuse(&format!(
            "draws blades at most {most} m away: --blade-distance {} is too far (the ground reaches --view-distance)",
            settings.culling.blade_range()
        ));
    }
    Ok(())
}

/// `settings` with the blade class's rows the animation needs (`Mode::draw_rows`: the sine per
/// cluster draws a row per tile), else as given.
pub(crate) fn with_mode_rows(
    mut settings: RenderSettings,
    animation: &crate::render::animation::AnimationSettings,
) -> RenderSettings {
    if let Some(rows) = animation.mode.draw_rows() {
        settings.culling.rows = rows;
    }
    settings
}
