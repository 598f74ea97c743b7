//! `meadow overhead`: the cost of submitting the same blades in different ways. For each cluster
//! count, every submission strategy (`render::submission::Strategy`) renders the same static
//! scene, interleaved frame by frame like `meadow bench`; per frame the CPU time to record the
//! command buffer and to submit it, and the GPU time. Reported per (clusters, strategy): CPU µs
//! to record and to submit, ns of recording per draw the GPU executes, draws per second of CPU
//! time, GPU ms. Strategies the device cannot run are reported as unsupported.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;

use crate::app::write_text;
use crate::error::{Error, Result};
use crate::harness::document::{number, to_json, Header, Outcome, Summary};
use crate::harness::measure::{measure, Offscreen, Schedule};
use crate::harness::Progress;
use crate::render::animation::{AnimationSettings, Mode};
use crate::render::submission::{Strategy, Submission};
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

pub mod document;

pub use document::{OverheadDocument, OverheadFrame, OverheadRow, StrategyMeasured};

/// What to measure.
#[derive(Clone, Debug)]
pub struct OverheadOptions {
    /// Blades of the scene.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Cluster counts (draws of the per-cluster strategies).
    pub clusters: Vec<u32>,
    /// Strategies.
    pub strategies: Vec<Strategy>,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per strategy discarded first.
    pub warmup: u32,
    /// Frames per strategy measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
}

/// Run the measurement; `progress(done, total)` after every frame. Returns the document.
pub fn run(
    device: &Arc<Device>,
    options: &OverheadOptions,
    mut progress: impl FnMut(u64, u64),
) -> Result<OverheadDocument> {
    check(options)?;
    let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(options.blades));
    crate::app::check_limits(device, options.blades, (options.size, Default::default(), false), cells)?;
    // Created only once the input is known good: bad input leaves no empty directory.
    let scene = Scene::generate(options.blades, 1);
    let camera = scene.default_camera();
    let setup = Setup { device, camera, scene, options };
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let total = (options.clusters.len() * options.strategies.len()) as u64 * u64::from(options.warmup + options.frames);
    let mut progress = Progress::new(total, &mut progress);
    let mut rows = Vec::new();
    let mut target = OffscreenTarget::new(device, extent)?;
    let result = options
        .clusters
        .iter()
        .try_for_each(|&clusters| measure_clusters(&setup, &mut target, clusters, &mut progress, &mut rows));
    // SAFETY: every renderer waited for its frames when dropped (they are gone by now).
    unsafe { target.destroy(device) };
    result?;
    Ok(OverheadDocument {
        header: Header::new(device, "overhead", options.size),
        worker_threads: std::thread::available_parallelism().map_or(2, |n| n.get()),
        blades: options.blades,
        segments: options.segments,
        warmup: options.warmup,
        frames_per_strategy: options.frames,
        rows,
    })
}

/// Refuse options with nothing to measure, or clusters without blades.
fn check(options: &OverheadOptions) -> Result<()> {
    if options.strategies.is_empty() || options.clusters.is_empty() {
        return Err(Error::bad_input("nothing to measure: give at least one strategy and one cluster count"));
    }
    if let Some(c) = options.clusters.iter().find(|c| **c > options.blades) {
        return Err(Error::bad_input(format!(
            "--clusters {c} exceeds --blades {}: a cluster holds a blade at least",
            options.blades
        )));
    }
    Ok(())
}

/// What every cluster count is measured with: the device, the one static scene and its camera.
struct Setup<'a> {
    device: &'a Arc<Device>,
    scene: Scene,
    camera: Camera,
    options: &'a OverheadOptions,
}

/// Every strategy at `clusters`: a row per strategy onto `rows`, unsupported ones with the reason.
fn measure_clusters(
    setup: &Setup,
    target: &mut OffscreenTarget,
    clusters: u32,
    progress: &mut Progress,
    rows: &mut Vec<OverheadRow>,
) -> Result<()> {
    let options = setup.options;
    // Build what the device supports; the rest is reported.
    let mut renderers = Vec::new();
    for &strategy in &options.strategies {
        if let Some(why) = strategy.unsupported(setup.device, clusters) {
            let outcome = Outcome::Unsupported { unsupported: why };
            rows.push(OverheadRow { clusters, strategy: strategy.name().into(), outcome });
            progress.skipped(u64::from(options.warmup + options.frames));
            continue;
        }
        // Driver overhead of the submission strategies: every stored blade, no cull pass.
        let brute_force = crate::render::culling::Culling::brute_force(options.segments);
        let settings = RenderSettings {
            submission: Submission { strategy, clusters },
            ..RenderSettings::offscreen(options.segments, brute_force)
        };
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        renderers.push((strategy, Renderer::new(setup.device.clone(), &setup.scene, settings, animation)?));
    }
    let (strategies, mut built): (Vec<Strategy>, Vec<Renderer>) = renderers.into_iter().unzip();
    let mut subject = Offscreen {
        renderers: &mut built,
        targets: std::slice::from_mut(target),
        camera: &|_, _| setup.camera,
        time: &|_| 0.0,
        after: None,
    };
    let measured = measure(&mut subject, Schedule { warmup: options.warmup, frames: options.frames }, progress)?;
    for (i, strategy) in strategies.into_iter().enumerate() {
        let frames = measured
            .timings(i)
            .map(|t| OverheadFrame {
                cpu_record_us: t.cpu_record_ms * 1e3,
                cpu_submit_us: t.cpu_submit_ms * 1e3,
                gpu_ms: t.gpu_ms,
                readback_ms: Some(t.readback_ms),
            })
            .collect();
        let outcome = Outcome::Measured(strategy_row(strategy, clusters, frames));
        rows.push(OverheadRow { clusters, strategy: strategy.name().into(), outcome });
    }
    Ok(())
}

/// What `strategy` at `clusters` measured, from its measured frames.
fn strategy_row(strategy: Strategy, clusters: u32, frames: Vec<OverheadFrame>) -> StrategyMeasured {
    let column = |f: fn(&OverheadFrame) -> f64| Summary::of(&frames.iter().map(f).collect::<Vec<f64>>());
    let record = column(|f| f.cpu_record_us);
    let (record_us, submit_us, gpu_ms) =
        (record.median, column(|f| f.cpu_submit_us).median, column(|f| f.gpu_ms).median);
    let gpu_draws = strategy.gpu_draws(clusters);
    let cpu_s = (record_us + submit_us) * 1e-6;
    StrategyMeasured {
        draw_calls_recorded: strategy.blade_draws(clusters),
        draws_executed: gpu_draws,
        cpu_record_us: record_us,
        cpu_submit_us: submit_us,
        cpu_record_us_p95: record.p95,
        ns_per_draw: record_us * 1e3 / f64::from(gpu_draws),
        draws_per_second: if cpu_s > 0.0 { f64::from(gpu_draws) / cpu_s } else { 0.0 },
        gpu_ms,
        readback_ms: Some(column(|f| f.readback_ms.unwrap_or(0.0)).median),
        frames,
    }
}

/// The report table.
pub fn table(doc: &OverheadDocument) -> String {
    let mut out = format!(
        "{:>8} {:<12} {:>7} {:>7} {:>11} {:>11} {:>10} {:>12} {:>9}\n",
        "clusters", "strategy", "calls", "draws", "record µs", "submit µs", "ns/draw", "draws/s", "GPU ms"
    );
    for row in &doc.rows {
        let (clusters, strategy) = (row.clusters, &row.strategy);
        let m = match &row.outcome {
            Outcome::Unsupported { unsupported: why } => {
                out.push_str(&format!("{clusters:>8} {strategy:<12} unsupported: {why}\n"));
                continue;
            }
            Outcome::Measured(m) => m,
        };
        out.push_str(&format!(
            "{:>8} {:<12} {:>7} {:>7} {:>11.1} {:>11.1} {:>10.1} {:>12.3e} {:>9.2}\n",
            clusters,
            strategy,
            m.draw_calls_recorded,
            m.draws_executed,
            m.cpu_record_us,
            m.cpu_submit_us,
            m.ns_per_draw,
            m.draws_per_second,
            m.gpu_ms,
        ));
    }
    out.push_str(
        "record µs: whole frame (terrain, barriers, readback copy included); ns/draw: recording per draw executed; \
         draws/s: draws executed per second of record + submit\n",
    );
    out
}

/// Tidy CSV: one line per measured frame.
pub fn csv(doc: &OverheadDocument) -> String {
    let mut out = String::from("clusters,strategy,frame,cpu_record_us,cpu_submit_us,gpu_ms\n");
    for row in &doc.rows {
        let Some(m) = row.outcome.measured() else { continue };
        for (i, f) in m.frames.iter().enumerate() {
            out.push_str(&format!(
                "{},{},{},{},{},{}\n",
                row.clusters,
                row.strategy,
                i,
                number(f.cpu_record_us),
                number(f.cpu_submit_us),
                number(f.gpu_ms)
            ));
        }
    }
    out
}

/// Write overhead.json, overhead.csv and overhead.png into `dir`.
/// The files of a run, one set: the report, its table, its chart.
pub const FILES: [&str; 3] = ["overhead.json", "overhead.csv", "overhead.png"];

pub fn write(doc: &OverheadDocument, dir: &Path) -> Result<()> {
    let text = to_json(doc);
    let [json, table, chart] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(doc))?;
    plot(doc, &dir.join(chart))
}

/// `overhead.png`: CPU record + submit per frame, recording ns per draw and GPU ms against the
/// cluster count, one series per strategy.
pub fn plot(doc: &OverheadDocument, path: &Path) -> Result<()> {
    use crate::harness::plot::{line_panels, Panel, Scale, Series};
    let rows: Vec<(&OverheadRow, &StrategyMeasured)> =
        doc.rows.iter().filter_map(|r| Some((r, r.outcome.measured()?))).collect();
    let mut strategies: Vec<&str> = Vec::new();
    for (r, _) in &rows {
        if !strategies.contains(&r.strategy.as_str()) {
            strategies.push(&r.strategy);
        }
    }
    let clusters: std::collections::BTreeSet<u32> = rows.iter().map(|(r, _)| r.clusters).collect();
    let x_scale = if clusters.len() > 1 { Scale::Log } else { Scale::Linear };
    let series = |value: &dyn Fn(&StrategyMeasured) -> f64| -> Vec<Series> {
        strategies
            .iter()
            .map(|s| Series {
                label: s.to_string(),
                points: rows
                    .iter()
                    .filter(|(r, _)| r.strategy == *s)
                    .map(|(r, m)| (f64::from(r.clusters), value(m)))
                    .filter(|p| p.1 > 0.0 && p.1.is_finite())
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    let panel = |title: &str, y: &str, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: "clusters (draws)".into(),
        y_label: y.into(),
        x_scale,
        y_scale: Scale::Log,
        series,
    };
    let panels: Vec<Panel> = [
        panel("CPU record + submit per frame", "µs (median)", series(&|m| m.cpu_record_us + m.cpu_submit_us)),
        panel("Recording per draw executed", "ns per draw", series(&|m| m.ns_per_draw)),
        panel("GPU time per frame", "GPU ms (median)", series(&|m| m.gpu_ms)),
    ]
    .into_iter()
    .filter(|p| !p.series.is_empty())
    .collect();
    if panels.is_empty() {
        return Ok(());
    }
    let title = format!("meadow overhead: {} blades x {} segments on {}", doc.blades, doc.segments, doc.header.device);
    line_panels(path, (560 * panels.len() as u32, 480), &title, &panels, panels.len())
}
