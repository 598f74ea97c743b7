//! What `meadow bench` makes of its JSON document: the thesis-shaped table, the pipeline
//! statistics table, the CSV, the chart, and the comparison of two runs.

use std::path::Path;

use super::document::{BenchDocument, BenchRow};
use super::THESIS_TABLE;
use crate::app::write_text;
use crate::error::Result;
use crate::harness::document::{number, to_json};

/// Pipeline statistics of the blade (or floor) pass per row and variant: what the driver was
/// asked to do, to read the frame times against.
pub fn statistics_table(doc: &BenchDocument) -> String {
    let mut out = format!(
        "{:>9} {:>4} {:<16} {:>12} {:>12} {:>12} {:>14} {:>9}\n",
        "blades", "seg", "variant", "VS invoc.", "clip prims", "FS invoc.", "FS/pixel", "ns/vertex"
    );
    let [w, h] = doc.header.resolution;
    let pixels = (f64::from(w) * f64::from(h)).max(1.0);
    for row in &doc.rows {
        for v in &row.variants {
            let Some(measured) = v.outcome.measured() else { continue };
            let Some(s) = measured.pipeline_statistics.get("blades") else { continue };
            let (vs, fs) = (s.vertex_invocations, s.fragment_invocations);
            let ms = measured.gpu_ms.median;
            out.push_str(&format!(
                "{:>9} {:>4} {:<16} {:>12} {:>12} {:>12} {:>14.2} {:>9.1}\n",
                row.blades,
                row.segments,
                v.variant,
                vs,
                s.clipping_primitives,
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

/// Median GPU ms of `variant` in a row (`None` when it was not measured).
pub fn median(row: &BenchRow, variant: &str) -> Option<f64> {
    Some(row.variant(variant)?.gpu_ms.median)
}

/// The best (lowest) median of a keyframed mode over its evaluation placements.
pub fn best(row: &BenchRow, mode: &str) -> Option<f64> {
    ["vertex", "blade"].iter().filter_map(|e| median(row, &format!("{mode}/{e}"))).min_by(f64::total_cmp)
}

/// The table shaped like thesis Table 6.2, with ratios next to the thesis' own.
pub fn table(doc: &BenchDocument) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "{:>9} {:>4} {:>10} | {:>7} {:>7} {:>7} | {:>6} {:>6} {:>6} | {:>6} {:>6} | {:>9}\n",
        "blades", "seg", "triangles", "FPS N", "FPS T", "FPS U", "T/N", "U/N", "N/floor", "thT/N", "thU/N", "cpu ms"
    ));
    for row in &doc.rows {
        let (blades, segments) = (row.blades, row.segments);
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
        let cpu = row.variant("static").map_or("-".to_string(), |v| format!("{:.3}", v.cpu_record_submit_ms.median));
        out.push_str(&format!(
            "{:>9} {:>4} {:>10} | {:>7} {:>7} {:>7} | {:>6} {:>6} {:>6} | {:>6} {:>6} | {:>9}\n",
            blades,
            segments,
            row.triangles,
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
pub fn csv(doc: &BenchDocument) -> String {
    let mut out = String::from(
        "blades,segments,variant,frame,gpu_ms,cpu_record_ms,cpu_submit_ms,cpu_wait_ms,\
         vertex_invocations,clipping_primitives,fragment_invocations\n",
    );
    for row in &doc.rows {
        for v in &row.variants {
            let Some(measured) = v.outcome.measured() else { continue };
            for (i, f) in measured.frames.iter().enumerate() {
                // Statistics columns: the blade (or floor) pass; empty without statistics.
                let blades = f.pipeline_statistics.get("blades");
                let stat = |count: fn(&crate::harness::document::Statistics) -> u64| {
                    blades.map_or(String::new(), |s| count(s).to_string())
                };
                out.push_str(&format!(
                    "{},{},{},{},{},{},{},{},{},{},{}\n",
                    row.blades,
                    row.segments,
                    v.variant,
                    i,
                    number(f.gpu_ms),
                    number(f.cpu_record_ms),
                    number(f.cpu_submit_ms),
                    number(f.cpu_wait_ms),
                    stat(|s| s.vertex_invocations),
                    stat(|s| s.clipping_primitives),
                    stat(|s| s.fragment_invocations),
                ));
            }
        }
    }
    out
}

/// Write bench.json, bench.csv and bench.png into `dir`.
/// The files of a run, one set: the report, its table, its chart.
pub const FILES: [&str; 3] = ["bench.json", "bench.csv", "bench.png"];

pub fn write(doc: &BenchDocument, dir: &Path) -> Result<()> {
    let text = to_json(doc);
    let [json, table, chart] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(doc))?;
    plot(doc, &dir.join(chart))
}

/// `bench.png`: per segment count, the median frame time of every variant against the blade
/// count (top row), and each variant's ratio to static (bottom row).
pub fn plot(doc: &BenchDocument, path: &Path) -> Result<()> {
    use crate::harness::plot::{line_panels, Panel, Scale, Series};
    let rows = &doc.rows;
    let mut segments: Vec<u32> = rows.iter().map(|r| r.segments).collect();
    segments.sort_unstable();
    segments.dedup();
    let mut names: Vec<String> = Vec::new();
    for row in rows {
        for v in &row.variants {
            if !names.contains(&v.variant) {
                names.push(v.variant.clone());
            }
        }
    }
    // Every variant in both rows, so a variant keeps its colour (static is 1 in the ratio row).
    let series = |seg: u32, value: &dyn Fn(&BenchRow, &str) -> Option<f64>| -> Vec<Series> {
        names
            .iter()
            .map(|name| Series {
                label: name.clone(),
                points: rows
                    .iter()
                    .filter(|r| r.segments == seg)
                    .filter_map(|r| Some((f64::from(r.blades), value(r, name)?)))
                    .filter(|p| p.1 > 0.0)
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    };
    let many = rows.iter().filter(|r| Some(r.segments) == segments.first().copied()).count() > 1;
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
    let [w, h] = doc.header.resolution;
    let title = format!("meadow bench: {} at {w}x{h}", doc.header.device);
    line_panels(path, size, &title, &panels, columns)
}

#[cfg(test)]
mod tests {
    use super::super::document::fixtures::{doc, row};
    use super::*;

    #[test]
    fn ratios_come_from_the_right_rows() {
        let row = |blades: u32, n: f64, t: f64| {
            row(blades, &[("static", &[n][..]), ("texture/vertex", &[t][..]), ("texture/blade", &[t * 0.9][..])])
        };
        let doc = doc(vec![row(40_000, 10.0, 12.0), row(360_000, 100.0, 150.0)]);
        let t = table(&doc);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[1].contains(" 1.08 "), "40k: 10.8 / 10: {}", lines[1]);
        assert!(lines[2].contains(" 1.35 "), "360k: 135 / 100: {}", lines[2]);
        assert!(lines[1].contains(" 1.08 ") && lines[1].contains("100.00"), "FPS N of 10 ms: {}", lines[1]);
        assert!(lines[1].ends_with(" 0.100"), "cpu record + submit of static: {}", lines[1]);
    }

    #[test]
    fn the_csv_writes_numbers_as_the_document_does() {
        let doc = doc(vec![row(1000, &[("static", &[2.0, 0.15][..])])]);
        let csv = csv(&doc);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[1..], ["1000,4,static,0,2.0,0.05,0.05,0.0,,,", "1000,4,static,1,0.15,0.05,0.05,0.0,,,"]);
    }
}
