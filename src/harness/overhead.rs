//! `meadow overhead`: the cost of submitting the same blades in different ways. For each cluster
//! count, every submission strategy (`render::submission::Strategy`) renders the same static
//! scene, interleaved frame by frame like `meadow bench`; per frame the CPU time to record the
//! command buffer and to submit it, and the GPU time. Reported per (clusters, strategy): CPU µs
//! to record and to submit, ns of recording per draw the GPU executes, draws per second of CPU
//! time, GPU ms. Strategies the device cannot run are reported as unsupported.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;
use serde_json::{json, Value};

use crate::app::write_text;
use crate::error::{Error, Result};
use crate::harness::document::summary;
use crate::harness::Progress;
use crate::render::animation::{AnimationSettings, Mode};
use crate::render::submission::{Strategy, Submission};
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

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

/// Run the measurement; `progress(done, total)` after every frame. Returns the JSON document.
pub fn run(device: &Arc<Device>, options: &OverheadOptions, mut progress: impl FnMut(u64, u64)) -> Result<Value> {
    check(options)?;
    let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(options.blades));
    crate::app::check_limits(device, options.blades, (options.size, Default::default()), cells)?;
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
    Ok(crate::harness::document::document(
        device,
        "overhead",
        options.size,
        json!({
        "worker_threads": std::thread::available_parallelism().map_or(2, |n| n.get()),
        "blades": options.blades,
        "segments": options.segments,
        "warmup": options.warmup,
        "frames_per_strategy": options.frames,
        "rows": rows,
        }),
    ))
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
    rows: &mut Vec<Value>,
) -> Result<()> {
    let options = setup.options;
    // Build what the device supports; the rest is reported.
    let mut renderers = Vec::new();
    for &strategy in &options.strategies {
        if let Some(why) = strategy.unsupported(setup.device, clusters) {
            rows.push(json!({ "clusters": clusters, "strategy": strategy.name(), "unsupported": why }));
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
    let mut frames: Vec<Vec<[f64; 4]>> = vec![Vec::new(); renderers.len()];
    for round in 0..options.warmup + options.frames {
        for (i, (_, renderer)) in renderers.iter_mut().enumerate() {
            let t = renderer.render_offscreen(target, &setup.camera, 0.0)?;
            progress.rendered()?;
            if round >= options.warmup {
                frames[i].push([t.cpu_record_ms * 1e3, t.cpu_submit_ms * 1e3, t.gpu_ms, t.readback_ms]);
            }
        }
    }
    for ((strategy, _), frames) in renderers.iter().zip(&frames) {
        rows.push(strategy_row(*strategy, clusters, frames));
    }
    Ok(())
}

/// The row of `strategy` at `clusters` from its measured frames (record µs, submit µs, GPU ms
/// of the passes, GPU ms of the read-back copy after them).
fn strategy_row(strategy: Strategy, clusters: u32, frames: &[[f64; 4]]) -> Value {
    let column = |k: usize| summary(&frames.iter().map(|f| f[k]).collect::<Vec<f64>>());
    let (record, submit, gpu) = (column(0), column(1), column(2));
    let median = |s: &Value| s["median"].as_f64().unwrap_or(0.0);
    let (record_us, submit_us, gpu_ms) = (median(&record), median(&submit), median(&gpu));
    let cpu_draws = strategy.blade_draws(clusters);
    let gpu_draws = strategy.gpu_draws(clusters);
    let cpu_s = (record_us + submit_us) * 1e-6;
    json!({
        "clusters": clusters,
        "strategy": strategy.name(),
        "draw_calls_recorded": cpu_draws,
        "draws_executed": gpu_draws,
        "cpu_record_us": record_us,
        "cpu_submit_us": submit_us,
        "cpu_record_us_p95": record["p95"],
        "ns_per_draw": record_us * 1e3 / f64::from(gpu_draws),
        "draws_per_second": if cpu_s > 0.0 { f64::from(gpu_draws) / cpu_s } else { 0.0 },
        "gpu_ms": gpu_ms,
        "readback_ms": median(&column(3)),
        "frames": frames
            .iter()
            .map(|f| json!({"cpu_record_us": f[0], "cpu_submit_us": f[1], "gpu_ms": f[2], "readback_ms": f[3]}))
            .collect::<Vec<_>>(),
    })
}

/// The report table.
pub fn table(doc: &Value) -> String {
    let mut out = format!(
        "{:>8} {:<12} {:>7} {:>7} {:>11} {:>11} {:>10} {:>12} {:>9}\n",
        "clusters", "strategy", "calls", "draws", "record µs", "submit µs", "ns/draw", "draws/s", "GPU ms"
    );
    for row in doc["rows"].as_array().into_iter().flatten() {
        let clusters = row["clusters"].as_u64().unwrap_or(0);
        let strategy = row["strategy"].as_str().unwrap_or("");
        if let Some(why) = row["unsupported"].as_str() {
            out.push_str(&format!("{clusters:>8} {strategy:<12} unsupported: {why}\n"));
            continue;
        }
        let f = |k: &str| row[k].as_f64().unwrap_or(0.0);
        out.push_str(&format!(
            "{:>8} {:<12} {:>7} {:>7} {:>11.1} {:>11.1} {:>10.1} {:>12.3e} {:>9.2}\n",
            clusters,
            strategy,
            row["draw_calls_recorded"].as_u64().unwrap_or(0),
            row["draws_executed"].as_u64().unwrap_or(0),
            f("cpu_record_us"),
            f("cpu_submit_us"),
            f("ns_per_draw"),
            f("draws_per_second"),
            f("gpu_ms"),
        ));
    }
    out.push_str(
        "record µs: whole frame (terrain, barriers, readback copy included); ns/draw: recording per draw executed; \
         draws/s: draws executed per second of record + submit\n",
    );
    out
}

/// Tidy CSV: one line per measured frame.
pub fn csv(doc: &Value) -> String {
    let mut out = String::from("clusters,strategy,frame,cpu_record_us,cpu_submit_us,gpu_ms\n");
    for row in doc["rows"].as_array().into_iter().flatten() {
        for (i, f) in row["frames"].as_array().into_iter().flatten().enumerate() {
            out.push_str(&format!(
                "{},{},{},{},{},{}\n",
                row["clusters"],
                row["strategy"].as_str().unwrap_or(""),
                i,
                f["cpu_record_us"],
                f["cpu_submit_us"],
                f["gpu_ms"]
            ));
        }
    }
    out
}

/// Write overhead.json, overhead.csv and overhead.png into `dir`.
/// The files of a run, one set: the report, its table, its chart.
pub const FILES: [&str; 3] = ["overhead.json", "overhead.csv", "overhead.png"];

pub fn write(doc: &Value, dir: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(doc).expect("a JSON value serialises");
    let [json, table, chart] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(doc))?;
    plot(doc, &dir.join(chart))
}

/// `overhead.png`: CPU record + submit per frame, recording ns per draw and GPU ms against the
/// cluster count, one series per strategy.
pub fn plot(doc: &Value, path: &Path) -> Result<()> {
    use crate::harness::plot::{line_panels, Panel, Scale, Series};
    let rows: Vec<&Value> =
        doc["rows"].as_array().into_iter().flatten().filter(|r| r["unsupported"].is_null()).collect();
    let mut strategies: Vec<&str> = Vec::new();
    for r in &rows {
        let s = r["strategy"].as_str().unwrap_or("");
        if !strategies.contains(&s) {
            strategies.push(s);
        }
    }
    let clusters: std::collections::BTreeSet<u64> = rows.iter().filter_map(|r| r["clusters"].as_u64()).collect();
    let x_scale = if clusters.len() > 1 { Scale::Log } else { Scale::Linear };
    let series = |value: &dyn Fn(&Value) -> f64| -> Vec<Series> {
        strategies
            .iter()
            .map(|s| Series {
                label: s.to_string(),
                points: rows
                    .iter()
                    .filter(|r| r["strategy"] == *s)
                    .filter_map(|r| Some((r["clusters"].as_f64()?, value(r))))
                    .filter(|p| p.1 > 0.0 && p.1.is_finite())
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    let f = |r: &Value, k: &str| r[k].as_f64().unwrap_or(0.0);
    let panel = |title: &str, y: &str, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: "clusters (draws)".into(),
        y_label: y.into(),
        x_scale,
        y_scale: Scale::Log,
        series,
    };
    let panels: Vec<Panel> = [
        panel(
            "CPU record + submit per frame",
            "µs (median)",
            series(&|r| f(r, "cpu_record_us") + f(r, "cpu_submit_us")),
        ),
        panel("Recording per draw executed", "ns per draw", series(&|r| f(r, "ns_per_draw"))),
        panel("GPU time per frame", "GPU ms (median)", series(&|r| f(r, "gpu_ms"))),
    ]
    .into_iter()
    .filter(|p| !p.series.is_empty())
    .collect();
    if panels.is_empty() {
        return Ok(());
    }
    let title = format!(
        "meadow overhead: {} blades x {} segments on {}",
        doc["blades"],
        doc["segments"],
        doc["device"].as_str().unwrap_or("?")
    );
    line_panels(path, (560 * panels.len() as u32, 480), &title, &panels, panels.len())
}
