//! The `meadow` command: parses the command line and dispatches to `meadow::app`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use meadow::app::{self, GpuOptions, RenderOptions, RenderReport};
use meadow::scene::Camera;
use meadow::vk::DeviceSelector;

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
    /// List the Vulkan devices with their drivers.
    Devices(GpuArgs),
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
    /// Number of grass blades (the field grows at a fixed density).
    #[arg(long, default_value = "100000", value_parser = meadow::cli::blade_count)]
    blades: u32,
    /// Bézier segments per blade (1..=16).
    #[arg(long, default_value = "4", value_parser = meadow::cli::segments)]
    segments: u32,
    /// Picture size.
    #[arg(long, default_value = "1280x720", value_name = "WxH", value_parser = meadow::cli::size)]
    size: (u32, u32),
    /// Seed of the terrain and the blade scatter.
    #[arg(long, default_value = "1")]
    seed: u64,
    /// Camera position and orientation in degrees (default: 1.7 m above the field's edge).
    #[arg(long, value_name = "X,Y,Z,YAW_DEG,PITCH_DEG", value_parser = meadow::cli::camera, allow_hyphen_values = true)]
    camera: Option<Camera>,
    /// Output PNG.
    #[arg(long, default_value = "meadow.png")]
    out: PathBuf,
    /// Blades per instance of the one blade draw (1 = classic per-blade instancing).
    #[arg(long, default_value = "1", value_parser = meadow::cli::blades_per_instance)]
    blades_per_instance: u32,
    /// Frames to render; the last is written, timings of all are summarised.
    #[arg(long, default_value = "1", value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    #[command(flatten)]
    gpu: GpuArgs,
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
            let options = RenderOptions {
                blades: args.blades,
                segments: args.segments,
                size: args.size,
                seed: args.seed,
                camera: args.camera,
                out: args.out,
                frames: args.frames,
                blades_per_instance: args.blades_per_instance,
            };
            let (result, validation) =
                app::with_device(&args.gpu.options(), false, |device| app::render(device, &options));
            (finish(result.map(|report| print_render(&report))), validation)
        }
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
    println!(
        "device: {} ({}, driver {} [{}])",
        d.name, d.api_version, d.driver_version, d.driver_info
    );
    println!(
        "scene: {} blades x {} segments on a {:.1} m field",
        report.blades, report.segments, report.field_m
    );
    println!(
        "triangles: {} ({} blades + {} terrain)",
        report.triangles.0 + report.triangles.1,
        report.triangles.0,
        report.triangles.1
    );
    let last = report.frames.last().expect("at least one frame");
    let passes: Vec<String> = last
        .passes
        .iter()
        .map(|p| format!("{} {:.3} ms", p.name, p.ms))
        .collect();
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
