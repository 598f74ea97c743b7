//! The `meadow` command: parses the command line and dispatches to `meadow::app`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use meadow::app::{self, GpuOptions, RenderOptions, RenderReport};
use meadow::keyframes::encoding::{Encoding, Packing};
use meadow::keyframes::{Representation, Smoothing};
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::scene::Camera;
use meadow::viewer::ViewerOptions;
use meadow::vk::swapchain::PresentMode;
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, GlobalWind, Wind};

/// A real-time grass renderer on raw Vulkan.
#[derive(Parser)]
#[command(name = "meadow", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render the grass field headless to a PNG and print what it cost.
    Render(RenderArgs),
    /// Open the interactive viewer (needs a display).
    View(ViewArgs),
    /// Measure static / texture / uniform / floor side by side (thesis Table 6.2), or compare runs.
    Bench(BenchArgs),
    /// Measure draw-submission overhead: the same blades drawn instanced, per cluster, indirectly,
    /// from secondaries recorded on threads, or pre-recorded.
    Overhead(OverheadArgs),
    /// Study a frame's GPU and CPU timing: per-pass percentiles, pipeline statistics, 1/2/3
    /// frames in flight, a frame-time histogram and a Chrome/Perfetto trace.
    Timing(TimingArgs),
    /// List the Vulkan devices with their drivers.
    Devices(GpuArgs),
    /// Generate the keyframe table; report its compression figures and export it as a picture.
    Keyframes(KeyframeArgs),
}

#[derive(Args)]
struct KeyframeArgs {
    /// Poses over the full circle (a quarter is stored).
    #[arg(long, default_value = "1000", value_parser = meadow::cli::poses)]
    poses: u32,
    /// Segments of the blade.
    #[arg(long, default_value = "4", value_parser = meadow::cli::segments)]
    segments: u32,
    /// Print raw and compressed sizes (thesis 3.3) and measured encoding errors (4.4).
    #[arg(long)]
    report: bool,
    /// Write the keyframe texture as a 16-bit PNG.
    #[arg(long, value_name = "PATH.png")]
    export: Option<PathBuf>,
}

#[derive(Args)]
struct GpuArgs {
    /// Enable the Khronos validation layer with synchronization validation; exit non-zero if it
    /// reports anything.
    #[arg(long)]
    validation: bool,
    /// Device index (see `meadow devices`) or a substring of its name.
    #[arg(long, value_name = "INDEX|NAME")]
    device: Option<String>,
}

#[derive(Args)]
struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output PNG.
    #[arg(long, default_value = "meadow.png")]
    out: PathBuf,
    /// Frames to render; the last is written, timings of all are summarised.
    #[arg(long, default_value = "1", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    #[command(flatten)]
    submission: SubmissionArgs,
    #[command(flatten)]
    gpu: GpuArgs,
}

/// How the blade draws are submitted, for `render` and `timing`.
#[derive(Args)]
struct SubmissionArgs {
    /// How the blade draws are submitted (see `meadow overhead`); the picture is the same.
    #[arg(long, default_value = "instanced", value_parser = meadow::cli::strategy)]
    submission: meadow::render::submission::Strategy,
    /// Clusters (draws) of the per-cluster, indirect and secondary submissions.
    #[arg(long, default_value = "64", value_parser = meadow::cli::clusters)]
    clusters: u32,
}

impl SubmissionArgs {
    fn submission(&self) -> meadow::render::submission::Submission {
        meadow::render::submission::Submission { strategy: self.submission, clusters: self.clusters }
    }
}

/// Scene, animation and picture flags shared by `render` and `view`.
#[derive(Args)]
struct SceneArgs {
    /// Number of grass blades (the field grows at a fixed density).
    #[arg(long, default_value = "100000", value_parser = meadow::cli::blade_count)]
    blades: u32,
    /// Bézier segments per blade (1..=16).
    #[arg(long, default_value = "4", value_parser = meadow::cli::segments)]
    segments: u32,
    /// Picture (or window) size.
    #[arg(long, default_value = "1280x720", value_name = "WxH", value_parser = meadow::cli::size)]
    size: (u32, u32),
    /// Seed of the terrain and the blade scatter.
    #[arg(long, default_value = "1")]
    seed: u64,
    /// Camera position and orientation in degrees (default: 1.7 m above the field's edge).
    #[arg(long, value_name = "X,Y,Z,YAW_DEG,PITCH_DEG", value_parser = meadow::cli::camera, allow_hyphen_values = true)]
    camera: Option<Camera>,
    /// Blades per instance of the one blade draw (1 = classic per-blade instancing).
    #[arg(long, default_value = "1", value_parser = meadow::cli::blades_per_instance)]
    blades_per_instance: u32,
    #[command(flatten)]
    animation: AnimationArgs,
    /// Debug view: `force` colours blades by force magnitude (thesis fig. 4.5 / 6.1c).
    #[arg(long, value_enum)]
    debug_view: Option<DebugViewArg>,
}

impl SceneArgs {
    fn options(&self, out: PathBuf, frames: u32) -> RenderOptions {
        RenderOptions {
            blades: self.blades,
            segments: self.segments,
            size: self.size,
            seed: self.seed,
            camera: self.camera,
            out,
            frames,
            blades_per_instance: self.blades_per_instance,
            animation: self.animation.settings(),
            time: self.animation.time,
            debug_force: matches!(self.debug_view, Some(DebugViewArg::Force)),
            submission: Default::default(),
        }
    }
}

#[derive(Args)]
struct ViewArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Presentation mode.
    #[arg(long, value_enum, default_value = "fifo")]
    present: PresentArg,
    /// Frames in flight.
    #[arg(long, default_value = "2", value_parser = clap::value_parser!(u32).range(1..=3))]
    frames_in_flight: u32,
    /// Quit after N frames.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    frames: Option<u64>,
    /// Timed actions to play (see scripts/viewer/*.txt).
    #[arg(long, value_name = "PATH")]
    script: Option<PathBuf>,
    /// Write the last frame to a PNG at exit.
    #[arg(long, value_name = "PATH.png")]
    screenshot: Option<PathBuf>,
    /// Treat the swapchain as out of date every N frames (tests the re-create path).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    inject_out_of_date: Option<u32>,
    #[command(flatten)]
    gpu: GpuArgs,
}

#[derive(Args)]
struct BenchArgs {
    /// thesis: the 15 rows of Table 6.2 at 1280x720; quick: a small smoke matrix.
    #[arg(long, value_enum, default_value = "quick")]
    preset: PresetArg,
    /// Blade counts (comma-separated), replacing the preset's.
    #[arg(long, value_delimiter = ',', value_parser = meadow::cli::blade_count)]
    blades: Vec<u32>,
    /// Segment counts (comma-separated), replacing the preset's.
    #[arg(long, value_delimiter = ',', value_parser = meadow::cli::segments)]
    segments: Vec<u32>,
    /// Modes (comma-separated).
    #[arg(long, value_delimiter = ',', value_enum)]
    modes: Vec<ModeArg>,
    /// Evaluation placements of the keyframed modes (comma-separated).
    #[arg(long, value_delimiter = ',', value_enum)]
    eval: Vec<EvalArg>,
    /// Picture size, replacing the preset's.
    #[arg(long, value_name = "WxH", value_parser = meadow::cli::size)]
    size: Option<(u32, u32)>,
    /// Frames per variant discarded first.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=1000))]
    warmup: Option<u32>,
    /// Frames per variant measured.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: Option<u32>,
    /// Directory for bench.json and bench.csv.
    #[arg(long, default_value = "bench-out")]
    out: PathBuf,
    /// Compare two bench.json files instead of measuring; exit 1 on a regression.
    #[arg(long, num_args = 2, value_names = ["OLD.json", "NEW.json"])]
    compare: Vec<PathBuf>,
    /// Noise threshold of --compare, in percent.
    #[arg(long, default_value = "10", value_parser = meadow::cli::finite_f32)]
    threshold: f32,
    #[command(flatten)]
    gpu: GpuArgs,
}

#[derive(Args)]
struct TimingArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Frames measured per run (one run each with 1, 2 and 3 frames in flight).
    #[arg(long, default_value = "30", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    /// Frames discarded at the start of each run.
    #[arg(long, default_value = "2", value_parser = clap::value_parser!(u32).range(0..=1000))]
    warmup: u32,
    /// Write a Chrome-trace / Perfetto JSON of CPU and GPU spans on one timeline.
    #[arg(long, value_name = "PATH.json")]
    trace: Option<PathBuf>,
    /// Directory for timing.json and the frame-time histogram.
    #[arg(long, default_value = "timing-out")]
    out: PathBuf,
    #[command(flatten)]
    submission: SubmissionArgs,
    #[command(flatten)]
    gpu: GpuArgs,
}

#[derive(Args)]
struct OverheadArgs {
    /// Blades of the scene.
    #[arg(long, default_value = "100000", value_parser = meadow::cli::blade_count)]
    blades: u32,
    /// Segments per blade.
    #[arg(long, default_value = "2", value_parser = meadow::cli::segments)]
    segments: u32,
    /// Cluster counts (comma-separated): the draws of the per-cluster strategies.
    #[arg(long, value_delimiter = ',', default_value = "1,100,1000,10000", value_parser = meadow::cli::clusters)]
    clusters: Vec<u32>,
    /// Strategies (comma-separated): instanced, per-cluster, indirect, mdi, mdi-count, secondary, prerecorded.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "instanced,per-cluster,indirect,mdi,mdi-count,secondary,prerecorded",
        value_parser = meadow::cli::strategy
    )]
    strategies: Vec<meadow::render::submission::Strategy>,
    /// Picture size.
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = meadow::cli::size)]
    size: (u32, u32),
    /// Frames per strategy discarded first.
    #[arg(long, default_value = "3", value_parser = clap::value_parser!(u32).range(0..=1000))]
    warmup: u32,
    /// Frames per strategy measured.
    #[arg(long, default_value = "20", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    /// Directory for overhead.json, overhead.csv and overhead.png.
    #[arg(long, default_value = "overhead-out")]
    out: PathBuf,
    #[command(flatten)]
    gpu: GpuArgs,
}

#[derive(Clone, Copy, ValueEnum)]
enum PresetArg {
    Thesis,
    Quick,
}

#[derive(Clone, Copy, ValueEnum)]
enum PresentArg {
    Fifo,
    Mailbox,
    Immediate,
}

/// How blades are posed.
#[derive(Clone, Copy, ValueEnum)]
enum ModeArg {
    /// Neutral blades, no forces.
    Static,
    /// Keyframes sampled from a texture in the vertex shader (thesis 4.4.1).
    Texture,
    /// Keyframes in a uniform array, two 16-bit values per word (thesis 4.4.2).
    Uniform,
    /// Benchmark floor: pre-expanded static triangles, flat colour.
    Floor,
}

#[derive(Clone, Copy, ValueEnum)]
enum PackingArg {
    /// The thesis' merge/extract in a 32-bit float.
    Thesis,
    /// Two snorm16 in a uint (exact).
    Snorm,
}

#[derive(Clone, Copy, ValueEnum)]
enum RepresentationArg {
    /// One record per vertex pair (the thesis).
    Vertex,
    /// Three displaced Bézier control points per pose, any segment count.
    Curve,
}

#[derive(Clone, Copy, ValueEnum)]
enum EvalArg {
    /// Per vertex in the vertex shader.
    Vertex,
    /// Once per blade in a compute pass that evaluates every level.
    Blade,
}

#[derive(Clone, Copy, ValueEnum)]
enum DebugViewArg {
    /// Force magnitude as colour, green (none) to red (strongest pose).
    Force,
}

#[derive(Clone, Copy, ValueEnum)]
enum SmoothingArg {
    Nearest,
    Linear,
    Slerp,
}

#[derive(Clone, Copy, ValueEnum)]
enum EncodingArg {
    Rgba8x2,
    Unorm16,
    Float32,
}

#[derive(Clone, Copy, ValueEnum)]
enum AttenuationArg {
    Cluster,
    Blade,
}

#[derive(Args)]
struct AnimationArgs {
    /// Animation mode.
    #[arg(long, value_enum, default_value = "texture")]
    mode: ModeArg,
    /// Keyframe poses over the full circle (a quarter is stored).
    #[arg(long, default_value = "1000", value_parser = meadow::cli::poses)]
    poses: u32,
    /// In-between poses (thesis 3.2.6).
    #[arg(long, value_enum, default_value = "nearest")]
    smoothing: SmoothingArg,
    /// Keyframe texture encoding (thesis 4.4.1).
    #[arg(long, value_enum, default_value = "unorm16")]
    encoding: EncodingArg,
    /// Uniform-array packing of two 16-bit values per word (thesis 4.4.2).
    #[arg(long, value_enum, default_value = "snorm")]
    packing: PackingArg,
    /// Keyframe representation: per vertex pair (thesis) or Bézier control points.
    #[arg(long, value_enum, default_value = "vertex")]
    keyframes: RepresentationArg,
    /// Where the per-blade part of the animation runs: every vertex, or once per blade (compute).
    #[arg(long, value_enum, default_value = "vertex")]
    eval: EvalArg,
    /// Where point sources are attenuated (thesis 4.5): at cluster corners or per blade.
    #[arg(long, value_enum, default_value = "cluster")]
    attenuation: AttenuationArg,
    /// Cluster edge in metres (thesis 3.2.2).
    #[arg(long, default_value = "1.0", value_parser = meadow::cli::cluster_size)]
    cluster_size: f32,
    /// Global wind: direction it blows towards (degrees from +x towards +z) and strength.
    #[arg(long, value_name = "DIR_DEG,STRENGTH", default_value = "30,0.3", value_parser = meadow::cli::wind, allow_hyphen_values = true)]
    wind: (f32, f32),
    /// Steady global wind, without gusts.
    #[arg(long)]
    no_gusts: bool,
    /// Point wind source (eq. 4.1), optionally moving; repeatable.
    #[arg(long, value_name = "X,Z,POWER,SIGMA[,VX,VZ]", value_parser = meadow::cli::source, allow_hyphen_values = true)]
    source: Vec<meadow::wind::PointSource>,
    /// Calm area where the wind is blocked (thesis 5.1); repeatable.
    #[arg(long, value_name = "X0,Z0,X1,Z1", value_parser = meadow::cli::calm, allow_hyphen_values = true)]
    calm: Vec<meadow::wind::CalmArea>,
    /// Collider pushing blades aside (thesis 5.2): sphere:X,Y,Z,R or ellipsoid:X,Y,Z,RX,RY,RZ; repeatable.
    #[arg(long, value_name = "SHAPE", value_parser = meadow::cli::collider, allow_hyphen_values = true)]
    collider: Vec<meadow::wind::Collider>,
    /// Simulation time of the picture in seconds.
    #[arg(long, default_value = "0", value_parser = meadow::cli::time)]
    time: f32,
}

impl AnimationArgs {
    fn settings(&self) -> AnimationSettings {
        AnimationSettings {
            mode: match self.mode {
                ModeArg::Static => Mode::Static,
                ModeArg::Texture => Mode::Texture,
                ModeArg::Uniform => Mode::Uniform,
                ModeArg::Floor => Mode::Floor,
            },
            packing: match self.packing {
                PackingArg::Thesis => Packing::Thesis,
                PackingArg::Snorm => Packing::Snorm,
            },
            representation: match self.keyframes {
                RepresentationArg::Vertex => Representation::Vertex,
                RepresentationArg::Curve => Representation::Curve,
            },
            eval: match self.eval {
                EvalArg::Vertex => Eval::Vertex,
                EvalArg::Blade => Eval::Blade,
            },
            poses: self.poses,
            smoothing: match self.smoothing {
                SmoothingArg::Nearest => Smoothing::Nearest,
                SmoothingArg::Linear => Smoothing::Linear,
                SmoothingArg::Slerp => Smoothing::Slerp,
            },
            encoding: match self.encoding {
                EncodingArg::Rgba8x2 => Encoding::Rgba8x2,
                EncodingArg::Unorm16 => Encoding::Unorm16,
                EncodingArg::Float32 => Encoding::Float32,
            },
            attenuation: match self.attenuation {
                AttenuationArg::Cluster => Attenuation::Cluster,
                AttenuationArg::Blade => Attenuation::Blade,
            },
            cluster_size: self.cluster_size,
            wind: Wind {
                global: Some(GlobalWind { direction_deg: self.wind.0, strength: self.wind.1, gusts: !self.no_gusts }),
                sources: self.source.clone(),
                calm: self.calm.clone(),
                colliders: self.collider.clone(),
            },
        }
    }
}

impl GpuArgs {
    fn options(&self) -> GpuOptions {
        GpuOptions {
            validation: self.validation,
            device: self.device.as_deref().map(DeviceSelector::parse).unwrap_or_default(),
        }
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help, --version
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            // One line: clap's first line already reads "error: …".
            let text = e.to_string();
            eprintln!("{}", text.lines().next().unwrap_or("error: invalid arguments"));
            return ExitCode::from(2);
        }
    };
    let (code, validation) = match cli.command {
        Command::Render(args) => {
            let mut options = args.scene.options(args.out.clone(), args.frames);
            options.submission = args.submission.submission();
            let (result, validation) =
                app::with_device(&args.gpu.options(), false, |device| app::render(device, &options));
            (finish(result.map(|report| print_render(&report))), validation)
        }
        Command::View(args) => {
            let script = match args.script.as_deref().map(meadow::viewer::script::Script::load).transpose() {
                Ok(script) => script,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(e.exit_code() as u8);
                }
            };
            let options = ViewerOptions {
                scene: args.scene.options(PathBuf::new(), 1),
                present: match args.present {
                    PresentArg::Fifo => PresentMode::Fifo,
                    PresentArg::Mailbox => PresentMode::Mailbox,
                    PresentArg::Immediate => PresentMode::Immediate,
                },
                frames_in_flight: args.frames_in_flight as usize,
                frames: args.frames,
                script,
                screenshot: args.screenshot,
                inject_out_of_date: args.inject_out_of_date,
            };
            let (result, validation) = meadow::viewer::run(&args.gpu.options(), options);
            let code = finish(result.map(|report| {
                println!(
                    "viewer: {} frames, {} swapchains created (at most {} alive at once), {} re-creations",
                    report.frames, report.swapchains.0, report.swapchains.1, report.recreations
                );
                if !report.stats.is_empty() {
                    println!("stats: {}", report.stats);
                }
            }));
            (code, validation)
        }
        Command::Bench(args) => match bench(args) {
            Ok((code, validation)) => (code, validation),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(e.exit_code() as u8);
            }
        },
        Command::Keyframes(args) => {
            let options = app::KeyframeOptions {
                poses: args.poses,
                segments: args.segments,
                report: args.report,
                export: args.export,
            };
            (finish(app::keyframes(&options).map(|text| print!("{text}"))), None)
        }
        Command::Overhead(args) => overhead(args),
        Command::Timing(args) => timing(args),
        Command::Devices(args) => {
            let (result, validation) = app::devices(&args.options());
            let code = finish(result.map(|devices| {
                for device in devices {
                    println!("{device}");
                }
            }));
            (code, validation)
        }
    };
    match validation {
        Some(count) => {
            println!("validation: {count} messages");
            if count > 0 && code == 0 {
                return ExitCode::from(1);
            }
            ExitCode::from(code)
        }
        None => ExitCode::from(code),
    }
}

/// Run a measuring command on the device of `gpu`: a progress bar with ETA on a terminal (none
/// otherwise) fed by `run`'s `progress(done, total)`, then `report` of its result. Returns the
/// exit code and the validation count.
fn measure<T>(
    gpu: &GpuArgs,
    unit: &str,
    run: impl FnOnce(&std::sync::Arc<meadow::vk::Device>, &mut dyn FnMut(u64, u64)) -> meadow::Result<T>,
    report: impl FnOnce(T),
) -> (u8, Option<u64>) {
    let bar = std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| {
        let bar = indicatif::ProgressBar::new(0);
        let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, ETA {{eta}}");
        bar.set_style(indicatif::ProgressStyle::with_template(&template).expect("valid template"));
        bar
    });
    let (result, validation) = app::with_device(&gpu.options(), false, |device| {
        run(device, &mut |done, total| {
            if let Some(bar) = &bar {
                bar.set_length(total);
                bar.set_position(done);
            }
        })
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    (finish(result.map(report)), validation)
}

/// `meadow timing`. Returns the exit code and validation count.
fn timing(args: TimingArgs) -> (u8, Option<u64>) {
    use meadow::harness::timing::{self, TimingOptions};
    let mut render = args.scene.options(PathBuf::new(), args.frames);
    render.submission = args.submission.submission();
    let options = TimingOptions { render, warmup: args.warmup, trace: args.trace, out: args.out };
    measure(
        &args.gpu,
        "runs",
        |device, progress| {
            let (doc, intervals) = timing::run(device, &options, progress)?;
            timing::write(&doc, &intervals, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", timing::report(&doc));
            if let Some(trace) = &options.trace {
                println!("wrote {}", trace.display());
            }
            println!("wrote {}/timing.json and timing.png", options.out.display());
        },
    )
}

/// `meadow overhead`. Returns the exit code and validation count.
fn overhead(args: OverheadArgs) -> (u8, Option<u64>) {
    use meadow::harness::overhead::{self, OverheadOptions};
    let options = OverheadOptions {
        blades: args.blades,
        segments: args.segments,
        clusters: args.clusters,
        strategies: args.strategies,
        size: args.size,
        warmup: args.warmup,
        frames: args.frames,
        out: args.out,
    };
    measure(
        &args.gpu,
        "frames",
        |device, progress| {
            let doc = overhead::run(device, &options, progress)?;
            overhead::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", overhead::table(&doc));
            println!("wrote {}/overhead.json, overhead.csv and overhead.png", options.out.display());
        },
    )
}

/// `meadow bench`: measure, or compare two runs. Returns the exit code and validation count.
fn bench(args: BenchArgs) -> meadow::Result<(u8, Option<u64>)> {
    use meadow::harness::bench;
    if let [old, new] = args.compare.as_slice() {
        let (report, regressed) = bench::compare(&bench::load(old)?, &bench::load(new)?, f64::from(args.threshold));
        print!("{report}");
        return Ok((u8::from(regressed), None));
    }
    let mut options = match args.preset {
        PresetArg::Thesis => bench::BenchOptions::thesis(args.out.clone()),
        PresetArg::Quick => bench::BenchOptions::quick(args.out.clone()),
    };
    let preset_blades: Vec<u32> = options.rows.iter().map(|r| r.0).collect();
    let preset_segments: Vec<u32> = options.rows.iter().map(|r| r.1).collect();
    if !args.blades.is_empty() || !args.segments.is_empty() {
        let blades = if args.blades.is_empty() { dedup(preset_blades) } else { args.blades.clone() };
        let segments = if args.segments.is_empty() { dedup(preset_segments) } else { args.segments.clone() };
        options.rows = segments.iter().flat_map(|s| blades.iter().map(move |b| (*b, *s))).collect();
    }
    if !args.modes.is_empty() {
        options.modes = args
            .modes
            .iter()
            .map(|m| match m {
                ModeArg::Static => Mode::Static,
                ModeArg::Texture => Mode::Texture,
                ModeArg::Uniform => Mode::Uniform,
                ModeArg::Floor => Mode::Floor,
            })
            .collect();
    }
    if !args.eval.is_empty() {
        options.evals =
            args.eval.iter().map(|e| if matches!(e, EvalArg::Blade) { Eval::Blade } else { Eval::Vertex }).collect();
    }
    options.size = args.size.unwrap_or(options.size);
    options.warmup = args.warmup.unwrap_or(options.warmup);
    options.frames = args.frames.unwrap_or(options.frames);
    Ok(measure(
        &args.gpu,
        "frames",
        |device, progress| {
            let doc = bench::run(device, &options, progress)?;
            bench::write(&doc, &options.out)?;
            Ok(doc)
        },
        |doc| {
            print!("{}", bench::table(&doc));
            print!("\n{}", bench::statistics_table(&doc));
            println!("wrote {}/bench.json, bench.csv and bench.png", options.out.display());
        },
    ))
}

fn dedup(mut values: Vec<u32>) -> Vec<u32> {
    values.sort_unstable();
    values.dedup();
    values
}

fn finish(result: meadow::Result<()>) -> u8 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code() as u8
        }
    }
}

fn print_render(report: &RenderReport) {
    let d = &report.device;
    println!("device: {} ({}, driver {} [{}])", d.name, d.api_version, d.driver_version, d.driver_info);
    println!("scene: {} blades x {} segments on a {:.1} m field", report.blades, report.segments, report.field_m);
    println!(
        "triangles: {} ({} blades + {} terrain)",
        report.triangles.0 + report.triangles.1,
        report.triangles.0,
        report.triangles.1
    );
    let last = report.frames.last().expect("at least one frame");
    let passes: Vec<String> = last.passes.iter().map(|p| format!("{} {:.3} ms", p.name, p.ms)).collect();
    println!("gpu: {:.3} ms ({})", last.gpu_ms, passes.join(", "));
    let cpu = last.cpu_record_ms + last.cpu_submit_ms + last.cpu_wait_ms;
    println!(
        "cpu: {cpu:.3} ms (record {:.3} ms, submit {:.3} ms, wait {:.3} ms); setup {:.0} ms",
        last.cpu_record_ms, last.cpu_submit_ms, last.cpu_wait_ms, report.setup_ms
    );
    if report.frames.len() > 1 {
        let mut gpu: Vec<f64> = report.frames.iter().map(|f| f.gpu_ms).collect();
        println!("gpu median over {} frames: {:.3} ms", gpu.len(), app::median(&mut gpu));
    }
    println!("wrote {} ({}x{})", report.out.display(), report.size.0, report.size.1);
}
