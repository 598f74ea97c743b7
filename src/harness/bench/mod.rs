//! `meadow bench`: thesis Table 6.2 reproduced on this device. For each (blades, segments) row
//! every variant (static, floor, texture and uniform keyframes per evaluation placement) is built
//! once and the variants are rendered interleaved, A B C A B C …, so their ratios survive a noisy
//! machine. Results go to `bench.json` (versioned, every frame), `bench.csv` (tidy) and a table.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;
use serde_json::{json, Value};

use crate::app::write_text;
use crate::error::{Error, Result};
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::target::{offscreen_bytes, OFFSCREEN_FORMAT};
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

/// Version of the JSON layout.
pub const SCHEMA_VERSION: u32 = 1;

/// Thesis Table 6.2: (blades, segments, FPS N, FPS T, FPS U) on a GeForce 8800 GTS.
pub const THESIS_TABLE: [(u32, u32, f64, f64, f64); 15] = [
    (40_000, 4, 433.0, 400.0, 364.0),
    (160_000, 4, 206.0, 170.0, 155.0),
    (360_000, 4, 98.0, 78.0, 69.0),
    (640_000, 4, 58.0, 47.0, 40.0),
    (1_000_000, 4, 39.0, 28.0, 25.0),
    (40_000, 8, 365.0, 328.0, 305.0),
    (160_000, 8, 111.0, 98.0, 92.0),
    (360_000, 8, 57.0, 44.0, 41.0),
    (640_000, 8, 33.0, 25.0, 23.0),
    (1_000_000, 8, 23.0, 16.0, 15.0),
    (40_000, 16, 214.0, 198.0, 177.0),
    (160_000, 16, 58.0, 52.0, 46.0),
    (360_000, 16, 31.0, 24.0, 21.0),
    (640_000, 16, 18.0, 13.0, 12.0),
    (1_000_000, 16, 12.0, 8.0, 7.0),
];

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// (blades, segments) rows.
    pub rows: Vec<(u32, u32)>,
    /// Modes.
    pub modes: Vec<Mode>,
    /// Evaluation placements (keyframed modes only).
    pub evals: Vec<Eval>,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
}

impl BenchOptions {
    /// `--preset thesis`: the 15 rows of Table 6.2 at 1280×720.
    pub fn thesis(out: PathBuf) -> Self {
        Self {
            rows: THESIS_TABLE.iter().map(|r| (r.0, r.1)).collect(),
            modes: vec![Mode::Static, Mode::Texture, Mode::Uniform, Mode::Floor],
            evals: vec![Eval::Vertex, Eval::Blade],
            size: (1280, 720),
            // 15 rows x 6 variants x 6 rounds: about 20 minutes on 2 cores with lavapipe.
            warmup: 1,
            frames: 5,
            out,
        }
    }

    /// `--preset quick`: a small matrix for smoke runs.
    pub fn quick(out: PathBuf) -> Self {
        Self {
            rows: vec![(10_000, 4), (20_000, 8)],
            modes: vec![Mode::Static, Mode::Texture, Mode::Uniform, Mode::Floor],
            evals: vec![Eval::Vertex, Eval::Blade],
            size: (320, 180),
            warmup: 1,
            frames: 3,
            out,
        }
    }
}

/// One variant of a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// Mode.
    pub mode: Mode,
    /// Evaluation placement.
    pub eval: Eval,
}

impl Variant {
    /// `texture/blade`, `static`, `floor`…
    pub fn name(&self) -> String {
        let mode = format!("{:?}", self.mode).to_lowercase();
        match self.mode {
            Mode::Static | Mode::Floor => mode,
            _ => format!("{mode}/{}", format!("{:?}", self.eval).to_lowercase()),
        }
    }
}

/// The variants of `options`: static and floor once, keyframed modes per evaluation placement.
pub fn variants(options: &BenchOptions) -> Vec<Variant> {
    let mut out = Vec::new();
    for mode in &options.modes {
        match mode {
            Mode::Static | Mode::Floor => out.push(Variant { mode: *mode, eval: Eval::Vertex }),
            _ => out.extend(options.evals.iter().map(|eval| Variant { mode: *mode, eval: *eval })),
        }
    }
    out
}

/// Percentile by nearest rank of sorted values.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil().max(1.0) as usize;
    sorted[rank.min(sorted.len()) - 1]
}

/// Median, p5, p95, p99 and maximum of unsorted values (nearest rank), as the JSON documents
/// of `bench`, `overhead` and `timing` report them.
pub fn summary(values: &[f64]) -> Value {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    json!({
        "median": percentile(&sorted, 50.0),
        "p5": percentile(&sorted, 5.0),
        "p95": percentile(&sorted, 95.0),
        "p99": percentile(&sorted, 99.0),
        "max": sorted.last().copied().unwrap_or(0.0),
    })
}

/// Run the benchmark; `progress(done, total)` after every frame. Returns the JSON document.
pub fn run(device: &Arc<Device>, options: &BenchOptions, mut progress: impl FnMut(u64, u64)) -> Result<Value> {
    let variants = variants(options);
    if variants.is_empty() || options.rows.is_empty() {
        return Err(Error::bad_input("nothing to measure: give at least one mode and one row"));
    }
    std::fs::create_dir_all(&options.out)
        .map_err(|source| Error::Io { path: options.out.display().to_string(), source })?;
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let total = (options.rows.len() * variants.len()) as u64 * u64::from(options.warmup + options.frames);
    let mut done = 0;
    let mut rows = Vec::new();
    for &(blades, segments) in &options.rows {
        let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
        crate::app::check_limits(device, blades, options.size, cells)?;
        let scene = Scene::generate(blades, 1);
        let camera = Camera::default_for(&scene.terrain);
        let mut target = OffscreenTarget::new(device, extent)?;
        // A variant the device cannot hold at this size (e.g. `--eval blade`'s records over
        // maxStorageBufferRange) is reported as unsupported for the row, not failed.
        let mut unsupported = Vec::new();
        let runnable: Vec<Variant> = variants
            .iter()
            .copied()
            .filter(|v| match crate::app::check_scene(device, blades, segments, options.size, &animation_of(v)) {
                Err(Error::BadInput(why)) => {
                    unsupported.push(json!({ "variant": v.name(), "unsupported": why }));
                    done += u64::from(options.warmup + options.frames);
                    false
                }
                _ => true,
            })
            .collect();
        let built: Result<Vec<Renderer>> = runnable
            .iter()
            .map(|v| {
                let animation = animation_of(v);
                let settings = RenderSettings {
                    segments,
                    color_format: OFFSCREEN_FORMAT,
                    encode_srgb: true,
                    frames_in_flight: 1,
                    blades_per_instance: 1,
                    debug_force: false,
                    wireframe: false,
                    pipeline_statistics: true,
                    submission: Default::default(),
                };
                Renderer::new(device.clone(), &scene, settings, animation)
            })
            .collect();
        let mut renderers = match built {
            Ok(r) => r,
            Err(e) => {
                // SAFETY: nothing was rendered into the target.
                unsafe { target.destroy(device) };
                return Err(e);
            }
        };
        let mut samples: Vec<Vec<Value>> = vec![Vec::new(); runnable.len()];
        let measured = (|| {
            // Interleaved: one frame of each variant per round; fixed simulation time step.
            for round in 0..options.warmup + options.frames {
                let time = round as f32 / 60.0;
                for (i, renderer) in renderers.iter_mut().enumerate() {
                    let t = renderer.render_offscreen(&mut target, &camera, time)?;
                    done += 1;
                    progress(done, total);
                    if round >= options.warmup {
                        let passes: serde_json::Map<String, Value> =
                            t.passes.iter().map(|p| (p.name.to_string(), json!(p.ms))).collect();
                        samples[i].push(json!({
                            "gpu_ms": t.gpu_ms,
                            "passes_ms": passes,
                            "pipeline_statistics": statistics_json(&t.passes),
                            "cpu_record_ms": t.cpu_record_ms,
                            "cpu_submit_ms": t.cpu_submit_ms,
                            "cpu_wait_ms": t.cpu_wait_ms,
                        }));
                    }
                }
            }
            Ok::<(), Error>(())
        })();
        let triangles = renderers.first().map_or(0, |r| r.triangles().0);
        drop(renderers);
        // SAFETY: every renderer waited for its frames when dropped.
        unsafe { target.destroy(device) };
        measured?;
        let mut variant_json: Vec<Value> = runnable
            .iter()
            .zip(&samples)
            .map(|(v, frames)| {
                let field =
                    |name: &str| -> Vec<f64> { frames.iter().map(|f| f[name].as_f64().unwrap_or(0.0)).collect() };
                let cpu: Vec<f64> = frames
                    .iter()
                    .map(|f| f["cpu_record_ms"].as_f64().unwrap_or(0.0) + f["cpu_submit_ms"].as_f64().unwrap_or(0.0))
                    .collect();
                json!({
                    "variant": v.name(),
                    "gpu_ms": summary(&field("gpu_ms")),
                    "cpu_record_submit_ms": summary(&cpu),
                    "cpu_wait_ms": summary(&field("cpu_wait_ms")),
                    // The counts are the same every frame (fixed scene and camera): the last frame's.
                    "pipeline_statistics": frames.last().map_or(Value::Null, |f| f["pipeline_statistics"].clone()),
                    "frames": frames,
                })
            })
            .collect();
        variant_json.extend(unsupported);
        rows.push(json!({ "blades": blades, "segments": segments, "triangles": triangles, "variants": variant_json }));
    }
    Ok(document(
        device,
        "bench",
        options.size,
        json!({
            "warmup": options.warmup,
            "frames_per_variant": options.frames,
            "memory_per_row_bytes": offscreen_bytes(extent),
            "rows": rows,
        }),
    ))
}

/// A JSON document of `kind` (`bench`, `overhead`, `timing`): the fields every one carries —
/// schema version, device, driver, Mesa/LLVM string, resolution, build profile, git commit,
/// `LP_NUM_THREADS` — followed by `fields`.
pub fn document(device: &Device, kind: &str, resolution: (u32, u32), fields: Value) -> Value {
    let info = &device.info;
    let mut doc = json!({
        "schema_version": SCHEMA_VERSION,
        "kind": kind,
        "device": info.name,
        "driver": format!("{} {}", info.driver_name, info.driver_version),
        "driver_info": info.driver_info,
        "resolution": [resolution.0, resolution.1],
        "build_profile": if cfg!(debug_assertions) { "debug" } else { "release" },
        "git_commit": option_env!("MEADOW_GIT_COMMIT").unwrap_or("unknown"),
        "lp_num_threads": std::env::var("LP_NUM_THREADS").ok(),
    });
    if let (Some(out), Value::Object(more)) = (doc.as_object_mut(), fields) {
        out.extend(more);
    }
    doc
}

/// Per pass, the pipeline statistics of a frame (`{}` when the device has none).
pub fn statistics_json(passes: &[crate::render::PassTime]) -> Value {
    let map: serde_json::Map<String, Value> = passes
        .iter()
        .filter_map(|p| {
            let s = p.statistics?;
            let fields: serde_json::Map<String, Value> =
                s.fields().iter().map(|(name, value)| (name.to_string(), json!(value))).collect();
            Some((p.name.to_string(), Value::Object(fields)))
        })
        .collect();
    Value::Object(map)
}

/// Pipeline statistics of the blade (or floor) pass per row and variant: what the driver was
/// asked to do, to read the frame times against.
pub fn statistics_table(doc: &Value) -> String {
    let mut out = format!(
        "{:>9} {:>4} {:<16} {:>12} {:>12} {:>12} {:>14} {:>9}\n",
        "blades", "seg", "variant", "VS invoc.", "clip prims", "FS invoc.", "FS/pixel", "ns/vertex"
    );
    let pixels =
        doc["resolution"].as_array().map_or(1.0, |r| r.iter().filter_map(Value::as_f64).product::<f64>().max(1.0));
    for row in doc["rows"].as_array().into_iter().flatten() {
        for v in row["variants"].as_array().into_iter().flatten() {
            let s = &v["pipeline_statistics"]["blades"];
            let Some(vs) = s["vertex_invocations"].as_u64() else { continue };
            let fs = s["fragment_invocations"].as_u64().unwrap_or(0);
            let ms = v["gpu_ms"]["median"].as_f64().unwrap_or(0.0);
            out.push_str(&format!(
                "{:>9} {:>4} {:<16} {:>12} {:>12} {:>12} {:>14.2} {:>9.1}\n",
                row["blades"].as_u64().unwrap_or(0),
                row["segments"].as_u64().unwrap_or(0),
                v["variant"].as_str().unwrap_or(""),
                vs,
                s["clipping_primitives"].as_u64().unwrap_or(0),
                fs,
                fs as f64 / pixels,
                if vs > 0 { ms * 1e6 / vs as f64 } else { 0.0 },
            ));
        }
    }
    out.push_str(
        "blade-pass counts from pipeline statistics queries; ns/vertex: median frame time per vertex invocation\n",
    );
    out
}

/// The animation of a variant: the CLI's default wind (30°, strength 0.3, gusts).
fn animation_of(v: &Variant) -> AnimationSettings {
    AnimationSettings {
        mode: v.mode,
        eval: v.eval,
        wind: crate::wind::Wind {
            global: Some(crate::wind::GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: true }),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Median GPU ms of `variant` in a row of the JSON document.
pub fn median(row: &Value, variant: &str) -> Option<f64> {
    row["variants"].as_array()?.iter().find(|v| v["variant"] == variant)?["gpu_ms"]["median"].as_f64()
}

/// The best (lowest) median of a keyframed mode over its evaluation placements.
pub fn best(row: &Value, mode: &str) -> Option<f64> {
    ["vertex", "blade"].iter().filter_map(|e| median(row, &format!("{mode}/{e}"))).min_by(f64::total_cmp)
}

/// The table shaped like thesis Table 6.2, with ratios next to the thesis' own.
pub fn table(doc: &Value) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "{:>9} {:>4} {:>10} | {:>7} {:>7} {:>7} | {:>6} {:>6} {:>6} | {:>6} {:>6} | {:>9}\n",
        "blades", "seg", "triangles", "FPS N", "FPS T", "FPS U", "T/N", "U/N", "N/floor", "thT/N", "thU/N", "cpu ms"
    ));
    for row in doc["rows"].as_array().into_iter().flatten() {
        let blades = row["blades"].as_u64().unwrap_or(0) as u32;
        let segments = row["segments"].as_u64().unwrap_or(0) as u32;
        let n = median(row, "static");
        let t = best(row, "texture");
        let u = best(row, "uniform");
        let floor = median(row, "floor");
        let fps = |ms: Option<f64>| ms.map_or("-".to_string(), |ms| format!("{:.2}", 1000.0 / ms));
        let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => format!("{:.2}", a / b),
            _ => "-".to_string(),
        };
        let thesis = THESIS_TABLE.iter().find(|r| r.0 == blades && r.1 == segments);
        let (tt, tu) =
            thesis.map_or(("-".into(), "-".into()), |r| (format!("{:.2}", r.2 / r.3), format!("{:.2}", r.2 / r.4)));
        let cpu = row["variants"]
            .as_array()
            .and_then(|vs| vs.iter().find(|v| v["variant"] == "static"))
            .and_then(|v| v["cpu_record_submit_ms"]["median"].as_f64())
            .map_or("-".to_string(), |ms| format!("{ms:.3}"));
        out.push_str(&format!(
            "{:>9} {:>4} {:>10} | {:>7} {:>7} {:>7} | {:>6} {:>6} {:>6} | {:>6} {:>6} | {:>9}\n",
            blades,
            segments,
            row["triangles"].as_u64().unwrap_or(0),
            fps(n),
            fps(t),
            fps(u),
            ratio(t, n),
            ratio(u, n),
            ratio(n, floor),
            tt,
            tu,
            cpu
        ));
    }
    out.push_str("T/N, U/N: frame-time ratios to static with the better evaluation placement; thT/N, thU/N: the thesis' (Table 6.2); cpu: record + submit of a static frame\n");
    out
}

/// Tidy CSV: one line per measured frame.
pub fn csv(doc: &Value) -> String {
    let mut out = String::from(
        "blades,segments,variant,frame,gpu_ms,cpu_record_ms,cpu_submit_ms,cpu_wait_ms,\
         vertex_invocations,clipping_primitives,fragment_invocations\n",
    );
    for row in doc["rows"].as_array().into_iter().flatten() {
        for v in row["variants"].as_array().into_iter().flatten() {
            for (i, f) in v["frames"].as_array().into_iter().flatten().enumerate() {
                // Statistics columns: the blade (or floor) pass; empty without statistics.
                let stat = |name: &str| {
                    f["pipeline_statistics"]["blades"][name].as_u64().map_or(String::new(), |v| v.to_string())
                };
                out.push_str(&format!(
                    "{},{},{},{},{},{},{},{},{},{},{}\n",
                    row["blades"],
                    row["segments"],
                    v["variant"].as_str().unwrap_or(""),
                    i,
                    f["gpu_ms"],
                    f["cpu_record_ms"],
                    f["cpu_submit_ms"],
                    f["cpu_wait_ms"],
                    stat("vertex_invocations"),
                    stat("clipping_primitives"),
                    stat("fragment_invocations"),
                ));
            }
        }
    }
    out
}

/// Write bench.json, bench.csv and bench.png into `dir`.
pub fn write(doc: &Value, dir: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(doc).expect("a JSON value serialises");
    write_text(&dir.join("bench.json"), &text)?;
    write_text(&dir.join("bench.csv"), &csv(doc))?;
    plot(doc, &dir.join("bench.png"))
}

/// `bench.png`: per segment count, the median frame time of every variant against the blade
/// count (top row), and each variant's ratio to static (bottom row).
pub fn plot(doc: &Value, path: &Path) -> Result<()> {
    use crate::harness::plot::{line_panels, Panel, Scale, Series};
    let rows: Vec<&Value> = doc["rows"].as_array().into_iter().flatten().collect();
    let mut segments: Vec<u64> = rows.iter().filter_map(|r| r["segments"].as_u64()).collect();
    segments.sort_unstable();
    segments.dedup();
    let mut names: Vec<String> = Vec::new();
    for row in &rows {
        for v in row["variants"].as_array().into_iter().flatten() {
            let name = v["variant"].as_str().unwrap_or("").to_string();
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    // Every variant in both rows, so a variant keeps its colour (static is 1 in the ratio row).
    let series = |seg: u64, value: &dyn Fn(&Value, &str) -> Option<f64>| -> Vec<Series> {
        names
            .iter()
            .map(|name| Series {
                label: name.clone(),
                points: rows
                    .iter()
                    .filter(|r| r["segments"].as_u64() == Some(seg))
                    .filter_map(|r| Some((r["blades"].as_f64()?, value(r, name)?)))
                    .filter(|p| p.1 > 0.0)
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    let many = rows.iter().filter(|r| r["segments"].as_u64() == segments.first().copied()).count() > 1;
    let x_scale = if many { Scale::Log } else { Scale::Linear };
    let mut panels = Vec::new();
    for &seg in &segments {
        panels.push(Panel {
            title: format!("{seg} segments: frame time"),
            x_label: "blades".into(),
            y_label: "GPU ms (median)".into(),
            x_scale,
            y_scale: Scale::Log,
            series: series(seg, &|r, n| median(r, n)),
        });
    }
    for &seg in &segments {
        panels.push(Panel {
            title: format!("{seg} segments: ratio to static"),
            x_label: "blades".into(),
            y_label: "frame time / static".into(),
            x_scale,
            y_scale: Scale::Linear,
            series: series(seg, &|r, n| Some(median(r, n)? / median(r, "static")?)),
        });
    }
    panels.retain(|p| !p.series.is_empty());
    if panels.is_empty() {
        return Ok(());
    }
    let columns = segments.len().max(1);
    let size = (560 * columns as u32, 900);
    let title = format!(
        "meadow bench: {} at {}x{}",
        doc["device"].as_str().unwrap_or("?"),
        doc["resolution"][0],
        doc["resolution"][1]
    );
    line_panels(path, size, &title, &panels, columns)
}

/// Read a bench.json.
pub fn load(path: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::bad_input(format!("{}: {e}", path.display())))?;
    let doc: Value = serde_json::from_str(&text)
        .map_err(|e| Error::bad_input(format!("{}: not a bench.json: {e}", path.display())))?;
    if doc["schema_version"].as_u64() != Some(u64::from(SCHEMA_VERSION)) {
        return Err(Error::bad_input(format!("{}: schema_version is not {SCHEMA_VERSION}", path.display())));
    }
    Ok(doc)
}

/// Compare two runs: per (row, variant) change of the median GPU time in %. Returns the report
/// and whether any change is a regression beyond `threshold_pct`.
pub fn compare(old: &Value, new: &Value, threshold_pct: f64) -> (String, bool) {
    let mut out =
        format!("{:>9} {:>4} {:<16} {:>10} {:>10} {:>8}\n", "blades", "seg", "variant", "old ms", "new ms", "change");
    let mut regressed = false;
    for row in new["rows"].as_array().into_iter().flatten() {
        let same = old["rows"]
            .as_array()
            .into_iter()
            .flatten()
            .find(|r| r["blades"] == row["blades"] && r["segments"] == row["segments"]);
        let Some(old_row) = same else { continue };
        for v in row["variants"].as_array().into_iter().flatten() {
            let name = v["variant"].as_str().unwrap_or("");
            let (Some(a), Some(b)) = (median(old_row, name), median(row, name)) else { continue };
            let change = 100.0 * (b - a) / a;
            let flag = if change > threshold_pct {
                regressed = true;
                "  REGRESSION"
            } else if change < -threshold_pct {
                "  faster"
            } else {
                ""
            };
            out.push_str(&format!(
                "{:>9} {:>4} {:<16} {:>10.3} {:>10.3} {:>7.1}%{flag}\n",
                row["blades"], row["segments"], name, a, b, change
            ));
        }
    }
    out.push_str(&format!("noise threshold: {threshold_pct:.1} %\n"));
    (out, regressed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 50.0), 50.0);
        assert_eq!(percentile(&v, 5.0), 5.0);
        assert_eq!(percentile(&v, 99.0), 99.0);
        assert_eq!(percentile(&[3.0], 95.0), 3.0);
    }

    #[test]
    fn ratios_come_from_the_right_rows_and_regressions_are_flagged() {
        let row = |blades: u32, n: f64, t: f64| {
            json!({"blades": blades, "segments": 4, "triangles": 8, "variants": [
                {"variant": "static", "gpu_ms": {"median": n}, "cpu_record_submit_ms": {"median": 0.1}},
                {"variant": "texture/vertex", "gpu_ms": {"median": t}},
                {"variant": "texture/blade", "gpu_ms": {"median": t * 0.9}},
            ]})
        };
        let doc = json!({"schema_version": 1, "rows": [row(40_000, 10.0, 12.0), row(360_000, 100.0, 150.0)]});
        let t = table(&doc);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[1].contains(" 1.08 "), "40k: 10.8 / 10: {}", lines[1]);
        assert!(lines[2].contains(" 1.35 "), "360k: 135 / 100: {}", lines[2]);
        assert!(lines[1].contains(" 1.08 ") && lines[1].contains("100.00"), "FPS N of 10 ms: {}", lines[1]);
        let slower = json!({"schema_version": 1, "rows": [row(40_000, 10.0, 12.0), row(360_000, 130.0, 150.0)]});
        let (report, regressed) = compare(&doc, &slower, 10.0);
        assert!(regressed && report.contains("REGRESSION"), "{report}");
        let (_, same) = compare(&doc, &doc, 10.0);
        assert!(!same);
    }
}
