//! The flag groups of the `meadow` subcommands, as clap parses them, and their conversion into
//! the options of [`crate::app`] and the harness.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use super::animation::{AnimationArg, AnimationArgs, DebugViewArg, EvalArg, ModeArg};
use super::culling::CullArgs;
use crate::app::values;
use crate::app::{GpuOptions, RenderOptions};
use crate::scene::CameraChoice;
use crate::vk::swapchain::PresentMode;
use crate::vk::DeviceSelector;

#[derive(Args)]
pub(crate) struct KeyframeArgs {
    /// Poses over the full circle (a quarter is stored).
    #[arg(long, default_value = "1000", value_parser = values::poses)]
    pub(crate) poses: u32,
    /// Segments of the blade.
    #[arg(long, default_value = "4", value_parser = values::segments)]
    pub(crate) segments: u32,
    /// Print raw and compressed sizes (thesis 3.3), measured encoding errors (4.4), the curve
    /// representation against vertex keyframes, and the pose error at 250, 1000 and 4000 poses.
    #[arg(long)]
    pub(crate) report: bool,
    /// Write the keyframe texture as a 16-bit PNG.
    #[arg(long, value_name = "PATH.png")]
    pub(crate) export: Option<PathBuf>,
}

#[derive(Args)]
pub(crate) struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub(crate) shell: clap_complete::Shell,
}

#[derive(Args)]
pub(crate) struct GpuArgs {
    /// Enable the Khronos validation layer with synchronization validation; exit non-zero if it
    /// reports anything.
    #[arg(long)]
    pub(crate) validation: bool,
    /// Device index (see `meadow devices`) or a substring of its name.
    #[arg(long, value_name = "INDEX|NAME")]
    pub(crate) device: Option<String>,
}

#[derive(Args)]
pub(crate) struct RenderArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// Output PNG.
    #[arg(long, default_value = "meadow.png")]
    pub(crate) out: PathBuf,
    /// Frames to render; the last is written, timings of all are summarised.
    #[arg(long, default_value = "1", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub(crate) frames: u32,
    #[command(flatten)]
    pub(crate) submission: SubmissionArgs,
    #[command(flatten)]
    pub(crate) gpu: GpuArgs,
}

/// How the blade draws are submitted, for `render` and `timing`.
#[derive(Args)]
pub(crate) struct SubmissionArgs {
    /// How the blade draws are submitted (see `meadow overhead`); the picture is the same.
    #[arg(long, default_value = "instanced", value_parser = values::strategy)]
    pub(crate) submission: crate::render::submission::Strategy,
    /// Clusters (draws) of the per-cluster, indirect and secondary submissions.
    #[arg(long, default_value = "64", value_parser = values::clusters)]
    pub(crate) clusters: u32,
}

impl SubmissionArgs {
    pub(crate) fn submission(&self) -> crate::render::submission::Submission {
        crate::render::submission::Submission { strategy: self.submission, clusters: self.clusters }
    }
}

/// Scene, animation and picture flags shared by `render` and `view`.
#[derive(Args)]
pub(crate) struct SceneArgs {
    /// Number of grass blades, stored on a square field that grows at a fixed density (default
    /// 100000). With none of --blades, --field, --brute-force, --mode floor, --submission and
    /// --debug-view bounds, `render` and `view` draw the landscape: an unbounded field from the
    /// landscape camera, the far field to a --view-distance of 2000 m.
    #[arg(long, value_parser = values::blade_count)]
    pub(crate) blades: Option<u32>,
    /// A field of camera-following blocks instead of stored blades: its side in metres, or
    /// `infinite` (Belyaev §2.1; with --density, not with --blades).
    #[arg(long, value_name = "SIZE_M|infinite", value_parser = values::field, conflicts_with = "blades", allow_hyphen_values = true)]
    pub(crate) field: Option<crate::render::field_gpu::FieldSize>,
    /// Blades per square metre of a --field or the default landscape (default 400).
    #[arg(long, value_name = "BLADES_PER_M2", value_parser = values::density, allow_hyphen_values = true)]
    pub(crate) density: Option<f32>,
    /// Bézier segments per blade (1..=16).
    #[arg(long, default_value = "4", value_parser = values::segments)]
    pub(crate) segments: u32,
    /// Picture (or window) size.
    #[arg(long, default_value = "1280x720", value_name = "WxH", value_parser = values::size)]
    pub(crate) size: (u32, u32),
    /// Seed of the terrain and the blade scatter.
    #[arg(long, default_value = "1")]
    pub(crate) seed: u64,
    /// Camera position and orientation in degrees (default: 1.7 m above the field's edge), or
    /// `landscape`: 20 m above the ground there, pitched -8°, where 1 km lies 12.7 px below the
    /// horizon at 720 rows.
    #[arg(long, value_name = "X,Y,Z,YAW_DEG,PITCH_DEG|landscape", value_parser = values::camera_choice, allow_hyphen_values = true)]
    pub(crate) camera: Option<CameraChoice>,
    /// The relief under a --field: `gentle` (±1.5 m, waves of 60 to 6 m) or `hills` (hundreds
    /// of metres long, up to about ±50 m).
    #[arg(long, value_enum)]
    pub(crate) relief: Option<ReliefArg>,
    /// The ground from a greyscale PNG (8 or 16 bits): black 0 m, white the --terrain-scale's Y
    /// up; stretched over a --field SIZE's square, repeated mirrored under an unbounded field,
    /// under stored blades over its centre.
    #[arg(long, value_name = "PATH.png")]
    pub(crate) heightmap: Option<PathBuf>,
    /// The --heightmap's (and the --cover's) extent in x and z and the height of white above
    /// black, in metres (default 1000,50,1000; under a --field SIZE, X and Z are SIZE).
    #[arg(long, value_name = "X,Y,Z", value_parser = values::terrain_scale)]
    pub(crate) terrain_scale: Option<crate::scene::heightmap::TerrainScale>,
    /// Where grass grows, from a PNG stretched over the --heightmap's extent (or the
    /// --terrain-scale's X and Z): red, or a greyscale map's grey, is the grass's density (0
    /// none, 255 full); green (or the grey) is the flowers' (--flowers), alpha ignored. Bare ground
    /// is earth.
    #[arg(long, value_name = "PATH.png")]
    pub(crate) cover: Option<PathBuf>,
    /// Leave ground steeper than DEG degrees bare (a soft edge 4° wide across it): a block
    /// field's cull skips its blades, a stored field's scatter places none there.
    #[arg(long, value_name = "DEG", value_parser = values::slope_limit, allow_hyphen_values = true)]
    pub(crate) slope_limit: Option<f32>,
    /// Group the blades in clumps of about SIZE_M metres (0.1 to 50): a clump's blades lean
    /// outwards together and share a tint and a height (off by default).
    #[arg(long, value_name = "SIZE_M", value_parser = values::clumps, allow_hyphen_values = true)]
    pub(crate) clumps: Option<crate::scene::clumps::Clumps>,
    /// Flowers among the blades, PER_M2 per square metre where the --cover's green is full (a
    /// flower takes a blade's place: at most the field's blade density): a head of petals on a
    /// stem that bends with the blades; with the cull and the blades' pose records (not with
    /// --brute-force, --mode floor or --eval vertex).
    #[arg(long, value_name = "PER_M2", value_parser = values::flowers, allow_hyphen_values = true)]
    pub(crate) flowers: Option<crate::scene::flowers::Flowers>,
    /// Fog density per metre (default 0.001: at 1 km a surface keeps 37 % of its colour; 0: no fog).
    #[arg(long, value_name = "DENSITY", value_parser = values::fog, allow_hyphen_values = true)]
    pub(crate) fog: Option<f32>,
    /// Blades per instance of the blade draws (1 = classic per-blade instancing; default 1 with
    /// --brute-force, 32 entries of the visible list with the cull).
    #[arg(long, value_parser = values::blades_per_instance)]
    pub(crate) blades_per_instance: Option<u32>,
    #[command(flatten)]
    pub(crate) animation: AnimationArgs,
    #[command(flatten)]
    pub(crate) culling: CullArgs,
    /// Debug view: `force` colours blades by force magnitude (thesis fig. 4.5 / 6.1c); `bounds`
    /// draws the force clusters' edges, coloured by the force at each corner.
    #[arg(long, value_enum)]
    pub(crate) debug_view: Option<DebugViewArg>,
    /// Multisample anti-aliasing: N samples per pixel, resolved in linear space (1 = off; the
    /// counts the device supports for meadow's attachment formats, lavapipe 1 and 4).
    #[arg(long, default_value = "1", value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub(crate) msaa: u32,
    /// With --msaa: keep the alpha test of the blade outline instead of turning its alpha into
    /// sample coverage (alpha to coverage, the default).
    #[arg(long)]
    pub(crate) no_alpha_to_coverage: bool,
    /// Whether the command line draws the default landscape (`default_scene::draws_landscape`,
    /// set after parsing).
    #[arg(skip)]
    pub(crate) landscape: bool,
}

impl SceneArgs {
    pub(crate) fn options(&self, out: PathBuf, frames: u32) -> RenderOptions {
        let landscape = self.landscape.then_some(crate::render::field_gpu::FieldSize(None));
        RenderOptions {
            blades: self.blades.unwrap_or(crate::scene::blades::DEFAULT_BLADES),
            segments: self.segments,
            size: self.size,
            seed: self.seed,
            camera: self.camera.or(self.landscape.then_some(CameraChoice::Landscape)),
            out,
            frames,
            blades_per_instance: self
                .blades_per_instance
                .unwrap_or(crate::render::settings::default_blades_per_instance(!self.culling.brute_force)),
            animation: self.animation.settings(!self.culling.brute_force),
            time: self.animation.time,
            debug_force: self.debug_view == Some(DebugViewArg::Force),
            debug_bounds: self.debug_view == Some(DebugViewArg::Bounds),
            debug_wind: self.debug_view == Some(DebugViewArg::Wind),
            debug_lod: self.debug_view == Some(DebugViewArg::Lod),
            debug_tiles: self.debug_view == Some(DebugViewArg::Tiles),
            debug_fresnel: self.debug_view == Some(DebugViewArg::Fresnel),
            debug_cover: self.debug_view == Some(DebugViewArg::Cover),
            debug_pressed: self.debug_view == Some(DebugViewArg::Pressed),
            debug_patches: self.debug_view == Some(DebugViewArg::Patches),
            debug_far: self.debug_view == Some(DebugViewArg::Far),
            culling: self.culling.culling(self.segments, self.landscape),
            relief: match self.relief {
                Some(ReliefArg::Hills) => crate::scene::field::ReliefKind::Hills,
                Some(ReliefArg::Gentle) | None => crate::scene::field::ReliefKind::Gentle,
            },
            clumps: self.clumps,
            flowers: self.flowers,
            fog: self.fog.unwrap_or(crate::render::frame::look::FOG_DENSITY),
            landscape: crate::app::landscape::Landscape {
                heightmap: self.heightmap.clone(),
                terrain_scale: self.terrain_scale,
                cover: self.cover.clone(),
                slope_limit_deg: self.slope_limit,
            },
            field: self.field.or(landscape).map(|size| crate::scene::field::FieldSpec {
                size: size.0,
                density: self.density.unwrap_or(crate::scene::blades::DENSITY_PER_M2),
            }),
            budget_ms: self.culling.budget_ms,
            floor: self.animation.mode.is_floor(),
            submission: Default::default(),
            msaa: crate::render::msaa::Msaa { samples: self.msaa, alpha_to_coverage: !self.no_alpha_to_coverage },
        }
    }
}

#[derive(Args)]
pub(crate) struct ViewArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// Presentation mode.
    #[arg(long, value_enum, default_value = "fifo")]
    pub(crate) present: PresentArg,
    /// Frames in flight.
    #[arg(long, default_value = "2", value_parser = clap::value_parser!(u32).range(1..=3))]
    pub(crate) frames_in_flight: u32,
    /// Quit after N frames.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) frames: Option<u64>,
    /// Timed actions to play (see scripts/viewer/*.txt).
    #[arg(long, value_name = "PATH")]
    pub(crate) script: Option<PathBuf>,
    /// Write the last frame to a PNG at exit.
    #[arg(long, value_name = "PATH.png")]
    pub(crate) screenshot: Option<PathBuf>,
    /// Treat the swapchain as out of date every N frames (tests the re-create path).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub(crate) inject_out_of_date: Option<u32>,
    /// Every N frames print `sample: frame F rss_kib R live_vulkan_objects L` (`make soak`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) sample_every: Option<u64>,
    /// No overlay (panels and timing graphs): for measurements. F1 hides and shows it otherwise.
    #[arg(long)]
    pub(crate) no_ui: bool,
    /// Screenshots include the overlay (by default they show the scene only).
    #[arg(long, conflicts_with = "no_ui")]
    pub(crate) screenshot_ui: bool,
    /// Where the overlay's capture button writes its traces (an existing directory).
    #[arg(long, value_name = "DIR")]
    pub(crate) capture_dir: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) gpu: GpuArgs,
}

#[derive(Args)]
pub(crate) struct BenchArgs {
    /// thesis: the 15 rows of Table 6.2 at 1280x720; quick: a small smoke matrix; lod: brute force
    /// against the GPU-driven cull and LOD on a 1M-blade field from four cameras; msaa: the cost
    /// and the temporal stability (a slow pan) of --msaa with and without alpha to coverage;
    /// animations: the blade responses side by side, culled, unbounded and at the thesis' sizes;
    /// response: each response's tips through a step gust, read back and charted; landscape: a
    /// heightmap exported from the relief against the relief, and a half-bare covering map against
    /// a full one; far: the landscape to 2 km with the far field against the blades alone to 150 m.
    #[arg(long, value_enum, default_value = "quick")]
    pub(crate) preset: PresetArg,
    /// Blade counts (comma-separated), replacing the preset's (lod: one, the stored field's).
    #[arg(long, value_delimiter = ',', value_parser = values::blade_count)]
    pub(crate) blades: Vec<u32>,
    /// Segment counts (comma-separated), replacing the preset's (lod: one).
    #[arg(long, value_delimiter = ',', value_parser = values::segments)]
    pub(crate) segments: Vec<u32>,
    /// Modes (comma-separated).
    #[arg(long, value_delimiter = ',', value_enum)]
    pub(crate) modes: Vec<ModeArg>,
    /// Evaluation placements of the keyframed modes (comma-separated).
    #[arg(long, value_delimiter = ',', value_enum)]
    pub(crate) eval: Vec<EvalArg>,
    /// The responses --preset animations compares (comma-separated; static is always measured,
    /// as every ratio's reference).
    #[arg(long, value_delimiter = ',', value_enum)]
    pub(crate) animations: Vec<AnimationArg>,
    /// The wind fields --preset animations measures the keyframes and the Verlet blades under
    /// (comma-separated; analytic is always measured, every other field adds its culled rows).
    #[arg(long, value_delimiter = ',', value_enum)]
    pub(crate) wind_fields: Vec<crate::cli::animation::WindFieldArg>,
    /// Picture size, replacing the preset's.
    #[arg(long, value_name = "WxH", value_parser = values::size)]
    pub(crate) size: Option<(u32, u32)>,
    /// Frames per variant discarded first.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub(crate) warmup: Option<u32>,
    /// Frames per variant measured.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub(crate) frames: Option<u32>,
    /// Directory for bench.json, bench.csv and bench.png (lod: lod.json, lod.csv and lod.png;
    /// msaa: msaa.json, msaa.csv and msaa-far-field.png; animations: animations.json and
    /// animations.csv; landscape: landscape.json).
    #[arg(long, default_value = "bench-out")]
    pub(crate) out: PathBuf,
    /// Compare two bench.json files instead of measuring; exit 1 on a regression.
    #[arg(long, num_args = 2, value_names = ["OLD.json", "NEW.json"])]
    pub(crate) compare: Vec<PathBuf>,
    /// Noise threshold of --compare, in percent (positive).
    #[arg(long, default_value = "10", value_parser = values::finite_f32, allow_hyphen_values = true)]
    pub(crate) threshold: f32,
    #[command(flatten)]
    pub(crate) gpu: GpuArgs,
}

#[derive(Args)]
pub(crate) struct TimingArgs {
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
    /// Frames measured per run (one run each with 1, 2 and 3 frames in flight).
    #[arg(long, default_value = "30", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub(crate) frames: u32,
    /// Frames discarded at the start of each run.
    #[arg(long, default_value = "2", value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub(crate) warmup: u32,
    /// Write a Chrome-trace / Perfetto JSON of CPU and GPU spans on one timeline.
    #[arg(long, value_name = "PATH.json")]
    pub(crate) trace: Option<PathBuf>,
    /// Directory for timing.json and the frame-time histogram.
    #[arg(long, default_value = "timing-out")]
    pub(crate) out: PathBuf,
    /// Fly the camera along its heading at this speed (m/s, one `--dt` a frame), at its height
    /// above the ground: the cost of the passes that follow the camera (the ground's fill, the
    /// wind's and the state store's grids) as it crosses their cells.
    #[arg(long, value_name = "M_PER_S", value_parser = values::fly_speed, allow_hyphen_values = true)]
    pub(crate) fly: Option<f32>,
    #[command(flatten)]
    pub(crate) submission: SubmissionArgs,
    #[command(flatten)]
    pub(crate) gpu: GpuArgs,
}

#[derive(Args)]
pub(crate) struct OverheadArgs {
    /// Blades of the scene.
    #[arg(long, default_value = "100000", value_parser = values::blade_count)]
    pub(crate) blades: u32,
    /// Segments per blade.
    #[arg(long, default_value = "2", value_parser = values::segments)]
    pub(crate) segments: u32,
    /// Cluster counts (comma-separated): the draws of the per-cluster strategies.
    #[arg(long, value_delimiter = ',', default_value = "1,100,1000,10000", value_parser = values::clusters)]
    pub(crate) clusters: Vec<u32>,
    /// Strategies (comma-separated): instanced, per-cluster, indirect, mdi, mdi-count, secondary, prerecorded.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "instanced,per-cluster,indirect,mdi,mdi-count,secondary,prerecorded",
        value_parser = values::strategy
    )]
    pub(crate) strategies: Vec<crate::render::submission::Strategy>,
    /// Picture size.
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = values::size)]
    pub(crate) size: (u32, u32),
    /// Frames per strategy discarded first.
    #[arg(long, default_value = "3", value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub(crate) warmup: u32,
    /// Frames per strategy measured.
    #[arg(long, default_value = "20", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub(crate) frames: u32,
    /// Directory for overhead.json, overhead.csv and overhead.png.
    #[arg(long, default_value = "overhead-out")]
    pub(crate) out: PathBuf,
    #[command(flatten)]
    pub(crate) gpu: GpuArgs,
}

/// `--relief`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ReliefArg {
    /// Gentle hills like the stored terrain's (about ±1.5 m, waves of 60 to 6 m).
    Gentle,
    /// Hills hundreds of metres long (waves of 800 to 220 m) under the gentle relief's detail.
    Hills,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum PresetArg {
    Thesis,
    Quick,
    Lod,
    Msaa,
    Animations,
    Response,
    Landscape,
    Plants,
    Interaction,
    Far,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum PresentArg {
    Fifo,
    Mailbox,
    Immediate,
}

impl GpuArgs {
    pub(crate) fn options(&self) -> GpuOptions {
        GpuOptions {
            validation: self.validation,
            device: self.device.as_deref().map(DeviceSelector::parse).unwrap_or_default(),
        }
    }
}

impl From<PresentArg> for PresentMode {
    fn from(present: PresentArg) -> Self {
        match present {
            PresentArg::Fifo => PresentMode::Fifo,
            PresentArg::Mailbox => PresentMode::Mailbox,
            PresentArg::Immediate => PresentMode::Immediate,
        }
    }
}
