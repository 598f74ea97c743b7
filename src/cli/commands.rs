//! The subcommands that run once and print a short report: `render`, `view`, `keyframes` and
//! `devices`. Each returns its exit code and the validation message count (if validating).

use std::path::PathBuf;

use super::args::{CompletionsArgs, GpuArgs, KeyframeArgs, RenderArgs, ViewArgs};
use crate::app::{self, RenderReport};
use crate::viewer::ViewerOptions;

/// `meadow render`.
pub(crate) fn render(args: RenderArgs) -> (u8, Option<u64>) {
    let mut options = args.scene.options(args.out.clone(), args.frames);
    options.submission = args.submission.submission();
    let (result, validation) = app::with_device(&args.gpu.options(), false, |device| app::render(device, &options));
    (finish(result.map(|report| print_render(&report))), validation)
}

/// `meadow view`. A script that does not load is `Err(exit code)`, before any window opens.
pub(crate) fn view(args: ViewArgs) -> Result<(u8, Option<u64>), u8> {
    let script =
        args.script.as_deref().map(crate::viewer::script::Script::load).transpose().map_err(|e| finish(Err(e)))?;
    let options = ViewerOptions {
        scene: args.scene.options(PathBuf::new(), 1),
        present: args.present.into(),
        frames_in_flight: args.frames_in_flight as usize,
        frames: args.frames,
        script,
        screenshot: args.screenshot,
        inject_out_of_date: args.inject_out_of_date,
        sample_every: args.sample_every,
        ui: !args.no_ui,
        screenshot_ui: args.screenshot_ui,
        capture_dir: args.capture_dir,
    };
    let (result, validation) = crate::viewer::run(&args.gpu.options(), options);
    let code = finish(result.map(|report| {
        let present = report.present.map_or("none".to_string(), |p| format!("{p:?}").to_lowercase());
        println!(
            "viewer: {} frames, {} swapchains created (at most {} alive at once), {} re-creations ({} injected); present {present}, {} frames in flight, overlay {}",
            report.frames,
            report.swapchains.0,
            report.swapchains.1,
            report.recreations,
            report.injected,
            report.frames_in_flight,
            if report.overlay { "on" } else { "off" }
        );
        if !report.stats.is_empty() {
            println!("stats: {}", report.stats);
        }
    }));
    Ok((code, validation))
}

/// `meadow keyframes`.
pub(crate) fn keyframes(args: KeyframeArgs) -> (u8, Option<u64>) {
    let options =
        app::KeyframeOptions { poses: args.poses, segments: args.segments, report: args.report, export: args.export };
    (finish(app::keyframes(&options).map(|text| print!("{text}"))), None)
}

/// `meadow devices`.
pub(crate) fn devices(args: GpuArgs) -> (u8, Option<u64>) {
    let (result, validation) = app::devices(&args.options());
    let code = finish(result.map(|(devices, portability)| {
        println!(
            "{}",
            match portability {
                true => "loader: VK_KHR_portability_enumeration enabled (portability implementations are listed)",
                false => "loader: no VK_KHR_portability_enumeration (portability implementations such as MoltenVK are not listed)",
            }
        );
        for device in devices {
            println!("{device}");
        }
    }));
    (code, validation)
}

/// `meadow completions SHELL`: the script, written whole to standard output (or exit 1 with one
/// `error:` line when it cannot be written, e.g. into a closed pipe).
pub(crate) fn completions(args: CompletionsArgs) -> (u8, Option<u64>) {
    use std::io::Write;
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut super::command(), "meadow", &mut script);
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(&script).and_then(|()| stdout.flush()) {
        Ok(()) => (0, None),
        Err(e) => {
            eprintln!("error: writing the {} completion script: {e}", args.shell);
            (1, None)
        }
    }
}

/// The exit code of a command's result; an error is printed as one `error: …` line.
pub(crate) fn finish(result: crate::Result<()>) -> u8 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            // What the loader said while failing to create the instance, after the error.
            crate::vk::instance::print_held_messages();
            e.exit_code() as u8
        }
    }
}

/// `render`'s scene line: the field, its blades and segments, and the ground's and plants' options.
fn scene_line(report: &RenderReport) -> String {
    match report.field {
        Some(field) => format!(
            "scene: {} field of {} m blocks at {} blades/m² ({} blades stored) x {} segments{}",
            field.size.map_or("an unbounded".to_string(), |s| format!("a {s} m")),
            crate::scene::field::BLOCK_SIZE,
            field.density,
            field.block_blades(),
            report.segments,
            report.landscape
        ),
        None => format!(
            "scene: {} blades x {} segments on a {:.1} m field{}",
            report.blades, report.segments, report.field_m, report.landscape
        ),
    }
}

/// `render`'s far-field line: the plants and triangles the last frame drew, the rings, the band,
/// and the atlas bake's GPU time (its passes, in the frame that ran them).
fn far_line(far: &crate::render::far_field::FarCounts, frames: &[crate::render::FrameTimings]) -> String {
    let rings = &far.rings;
    let bake = frames.iter().find_map(|frame| {
        let passes: Vec<f64> = frame.passes.iter().filter(|p| p.name.starts_with("far atlas")).map(|p| p.ms).collect();
        (!passes.is_empty()).then(|| passes.iter().sum::<f64>())
    });
    let bake =
        bake.map_or("baked in a warm-up frame".to_owned(), |ms| format!("atlas baked in {ms:.1} ms of GPU time"));
    format!(
        "far field: {} plants, {} triangles, on {} rings from {:.0} m to {:.0} m (lattice {:.0} m); band {:.0}–{:.0} m; {bake}",
        far.plants, far.triangles, rings.rings, rings.start, rings.view_distance, rings.step, rings.band_start, rings.blade_range
    )
}

/// What `meadow render` prints: device, scene, GPU and CPU cost of the last frame, the file.
fn print_render(report: &RenderReport) {
    let d = &report.device;
    // The device was made with this profile (`Device::profile`); the choice is a function of the
    // driver and the environment, so it is the same here.
    let profile = crate::vk::profile::Profile::choose(&d.driver_name).map_or("unknown", |p| p.name());
    println!(
        "device: {} ({}, driver {} [{}]), profile {profile}",
        d.name, d.api_version, d.driver_version, d.driver_info
    );
    println!("{}", scene_line(report));
    let last = report.frames.last().expect("at least one frame");
    // Drawn, not stored: the cull's count of the last frame when it ran.
    let blades = last.cull.map_or(report.triangles.0, |c| c.triangles());
    println!("triangles: {} ({} blades + {} terrain)", blades + report.triangles.1, blades, report.triangles.1);
    let (submission, per_instance) = report.submission;
    let strategy = submission.strategy;
    let clusters = match strategy.gpu_draws(2) > 1 {
        true => format!(" over {} clusters", submission.clusters),
        false => String::new(),
    };
    println!("submission: {}{clusters}, {per_instance} blades per instance", strategy.name());
    if let Some(cull) = &last.cull {
        println!("cull: {}", cull.summary());
    }
    if let Some((listed, live)) = report.patches {
        use crate::render::animation::patches::{RECORD_WORDS, STORE_BYTES};
        let kib = (live * u64::from(RECORD_WORDS) * 4) as f64 / 1024.0;
        let store = STORE_BYTES >> 20;
        println!("patches: {live} blades hold state ({kib:.0} KiB of records in a {store} MiB store); {listed} listed");
    }
    if let Some(far) = &report.far {
        println!("{}", far_line(far, &report.frames));
    }
    let (time, clock) = report.clock;
    let warm_up = match report.warm_up {
        (steps, true) => format!("{steps} warm-up steps"),
        (_, false) => "0 warm-up steps (the model and the wind field are stateless)".to_owned(),
    };
    println!("time: step {} of {:.3} ms at --time {time} s; {warm_up}", clock.steps_to(time.into()), clock.dt * 1e3);
    let passes: Vec<String> = last.passes.iter().map(|p| format!("{} {:.3} ms", p.name, p.ms)).collect();
    if last.gpu_available {
        println!(
            "gpu: {:.3} ms ({}; between passes {:.3} ms); read-back copy {:.3} ms",
            last.gpu_ms,
            passes.join(", "),
            last.between_passes_ms,
            last.readback_ms
        );
    } else {
        println!("gpu: unavailable ({} writes no timestamps on its queue)", report.device.name);
    }
    let cpu = last.cpu_record_ms + last.cpu_submit_ms + last.cpu_wait_ms;
    println!(
        "cpu: {cpu:.3} ms (record {:.3} ms, submit {:.3} ms, wait {:.3} ms); setup {:.0} ms",
        last.cpu_record_ms, last.cpu_submit_ms, last.cpu_wait_ms, report.setup_ms
    );
    if let Some((budget, scale)) = report.budget {
        let last: Vec<f64> = report.frames.iter().rev().take(10).map(|f| f.gpu_ms).collect();
        let mut last = last;
        println!(
            "budget: {budget} ms; LOD scale {scale:.3} at the last frame; gpu median of the last {} frames {:.3} ms",
            last.len(),
            app::median(&mut last)
        );
    }
    if report.frames.len() > 1 && last.gpu_available {
        let mut gpu: Vec<f64> = report.frames.iter().map(|f| f.gpu_ms).collect();
        println!("gpu median over {} frames: {:.3} ms", gpu.len(), app::median(&mut gpu));
    }
    for note in &report.notes {
        println!("note: {note}");
    }
    println!("wrote {} ({}x{})", report.out.display(), report.size.0, report.size.1);
}
