//! What `meadow bench --preset lod` makes of its JSON document: the table, the tidy CSV and the
//! chart, written whole or not at all.

use std::path::Path;

use super::document::{LodDocument, LodMeasuredRow, LodVariant};
use super::VARIANTS;
use crate::app::write_text;
use crate::error::Result;
use crate::harness::document::{number, to_json};
use crate::harness::plot::BarPanel;

/// Median GPU ms of variant `name` of a row (0 when absent).
fn median(row: &LodMeasuredRow, name: &str) -> f64 {
    row.variant(name).map_or(0.0, |v| v.gpu_ms.median)
}

/// The table printed after a run: per row, both medians, their ratio, the cull share, what the
/// GPU-driven path considered and drew, and the box-filtered difference.
pub fn table(doc: &LodDocument) -> String {
    let mut out = format!(
        "{:<20} {:>8} {:<8}| {:>9} {:>9} {:>6} {:>6} | {:>10} {:>9} {:>10} {:>10} | {:>6} {:>6} {:>6}\n",
        "row",
        "blades",
        "view",
        "brute ms",
        "GPU ms",
        "ratio",
        "cull",
        "considered",
        "drawn",
        "triangles",
        "brute tri",
        "mean",
        "p99",
        "max"
    );
    for row in &doc.rows {
        let gpu = row.variant(VARIANTS[1]);
        let count = |f: fn(&LodVariant) -> u64, v: Option<&LodVariant>| v.map_or(0, f);
        let percent =
            |f: fn(&super::DiffRecord) -> f64| row.diff.as_ref().map_or("-".to_string(), |d| format!("{:.2}", f(d)));
        out.push_str(&format!(
            "{:<20} {:>8} {:<8}| {:>9.2} {:>9.2} {:>6.2} {:>5.1}% | {:>10} {:>9} {:>10} {:>10} | {:>6} {:>6} {:>6}\n",
            row.label,
            row.blades,
            row.view,
            median(row, VARIANTS[0]),
            median(row, VARIANTS[1]),
            row.ratio,
            100.0 * row.cull_share,
            count(|v| v.counts.as_ref().map_or(0, |c| u64::from(c.considered)), gpu),
            count(|v| v.drawn_blades, gpu),
            count(|v| v.blade_triangles, gpu),
            count(|v| v.blade_triangles, row.variant(VARIANTS[0])),
            percent(|d| d.mean_percent),
            percent(|d| d.p99_percent),
            percent(|d| d.max_percent),
        ));
    }
    out.push_str(
        "brute / GPU ms: median GPU frame time; ratio: brute / GPU-driven; cull: the cull passes' share of the \
         GPU-driven frame; considered, drawn, triangles: GPU-driven blades and blade triangles; mean, p99, max: \
         |GPU-driven - brute force| of 8x8 block means, % of full scale\n",
    );
    out
}

/// Tidy CSV: one line per measured frame of each variant. `drawn_blades` and `blade_triangles`
/// are the variant's; the `diff_*` columns are the row's (GPU-driven against brute force), empty
/// on brute force's lines.
pub fn csv(doc: &LodDocument) -> String {
    let mut out = String::from(
        "label,field,blades,segments,view,variant,frame,gpu_ms,cull_ms,drawn_blades,blade_triangles,\
         diff_mean_percent,diff_p99_percent\n",
    );
    for row in &doc.rows {
        for v in &row.variants {
            let reference = v.variant == VARIANTS[0];
            // Empty for brute force (no difference to itself) and for a row of two scenes.
            let diff = |f: fn(&super::DiffRecord) -> f64| match &row.diff {
                Some(d) if !reference => f(d).to_string(),
                _ => String::new(),
            };
            let kind = match row.field {
                super::FieldRecord::Stored { .. } => "stored",
                super::FieldRecord::Blocks { .. } => "blocks",
            };
            for (i, f) in v.frames.iter().enumerate() {
                out.push_str(&format!(
                    "\"{}\",{},{},{},{},{},{},{},{},{},{},{},{}\n",
                    row.label.replace('"', "\"\""),
                    kind,
                    row.blades,
                    row.segments,
                    row.view,
                    v.variant,
                    i,
                    number(f.gpu_ms),
                    number(f.cull_ms),
                    v.drawn_blades,
                    v.blade_triangles,
                    diff(|d| d.mean_percent),
                    diff(|d| d.p99_percent),
                ));
            }
        }
    }
    out
}

/// Write lod.json, lod.csv and lod.png into `dir`.
/// The files of a run, one set: the report, its table, its chart.
pub const FILES: [&str; 3] = ["lod.json", "lod.csv", "lod.png"];

pub fn write(doc: &LodDocument, dir: &Path) -> Result<()> {
    let text = to_json(doc);
    let [json, table, chart] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(doc))?;
    plot(doc, &dir.join(chart))
}

/// `lod.png`, three bar charts with a bar group per row: the median frame time of brute force
/// and GPU-driven, the speed-up (brute / GPU-driven), and the box-filtered difference (mean and
/// 99th-percentile block) of the rows that have one (not a row of two scenes).
pub fn plot(doc: &LodDocument, path: &Path) -> Result<()> {
    let rows = doc.rows.len() as u32;
    let height = (180 + 90 * rows).clamp(420, 4000);
    let [w, h] = doc.header.resolution;
    let title =
        format!("meadow bench --preset lod: {} at {w}x{h}, {} segments", doc.header.device, doc.options.segments);
    crate::harness::plot::bar_panels(path, (1680, height), &title, &panels(doc), 3)
}

/// The panels of `lod.png`.
fn panels(doc: &LodDocument) -> Vec<BarPanel> {
    let rows = &doc.rows;
    let labels: Vec<String> = rows.iter().map(|r| r.label.clone()).collect();
    let values = |f: &dyn Fn(&LodMeasuredRow) -> f64| -> Vec<f64> { rows.iter().map(f).collect() };
    let compared: Vec<(&str, &super::DiffRecord)> =
        rows.iter().filter_map(|r| Some((r.label.as_str(), r.diff.as_ref()?))).collect();
    let panel = |title: &str, value_label: &str, groups: Vec<(String, Vec<f64>)>| BarPanel {
        title: title.into(),
        value_label: value_label.into(),
        categories: labels.clone(),
        groups,
    };
    let mut panels = vec![
        panel(
            "frame time",
            "GPU ms (median)",
            vec![
                ("brute force".into(), values(&|r| median(r, VARIANTS[0]))),
                ("GPU-driven".into(), values(&|r| median(r, VARIANTS[1]))),
            ],
        ),
        panel("speed-up", "brute force / GPU-driven", vec![(String::new(), values(&|r| r.ratio))]),
    ];
    // Only the rows with a difference: a row of two scenes (the unbounded field) has none.
    if !compared.is_empty() {
        panels.push(BarPanel {
            title: "difference to brute force".into(),
            value_label: "% of full scale, 8x8 blocks".into(),
            categories: compared.iter().map(|(label, _)| label.to_string()).collect(),
            groups: vec![
                ("mean".into(), compared.iter().map(|(_, d)| d.mean_percent).collect()),
                ("p99 block".into(), compared.iter().map(|(_, d)| d.p99_percent).collect()),
            ],
        });
    }
    panels
}

#[cfg(test)]
mod tests {
    use super::super::document::{CountsRecord, DiffRecord, FieldRecord, LodFrame, LodOptionsRecord};
    use super::*;

    #[test]
    fn the_difference_panel_has_only_the_rows_with_a_difference() {
        let mut doc = doc();
        let titles = |doc: &LodDocument| panels(doc).iter().map(|p| p.title.clone()).collect::<Vec<_>>();
        assert_eq!(titles(&doc), ["frame time", "speed-up", "difference to brute force"]);
        // A row of two scenes (an unbounded field against the stored reference) has none.
        doc.rows[1].diff = None;
        let all = panels(&doc);
        assert_eq!(all[0].categories.len(), 2);
        assert_eq!(all[2].categories, ["stored, \"above\""]);
        assert_eq!(all[2].groups[0].1, [1.25]);
        doc.rows[0].diff = None;
        assert_eq!(titles(&doc), ["frame time", "speed-up"], "no difference, no panel");
    }

    fn doc() -> LodDocument {
        let variant = |name: &str, ms: f64, drawn: u64| {
            let frame = LodFrame { gpu_ms: ms, cull_ms: 0.5, passes_ms: Default::default() };
            let counts = CountsRecord {
                considered: 1000,
                after_tiles: 0,
                after_density: 0,
                after_frustum: 0,
                after_orientation: 0,
                after_occlusion: 0,
                tiles_visible: 0,
                tiles: 0,
                drawn: vec![],
                bucket_segments: vec![],
                total_drawn: drawn,
                triangles: 8 * drawn,
                classes: vec![],
                thinning: None,
            };
            LodVariant {
                variant: name.into(),
                gpu_ms: crate::harness::document::Summary::of(&[ms]),
                cull_ms: crate::harness::document::Summary::of(&[0.5]),
                cull_share: 0.05,
                drawn_blades: drawn,
                blade_triangles: 8 * drawn,
                counts: Some(counts),
                frames: vec![frame.clone(), frame],
            }
        };
        let row = |label: &str, brute: f64, gpu: f64| LodMeasuredRow {
            label: label.into(),
            field: FieldRecord::Stored { blades: 1000, seed: 1 },
            blades: 1000,
            segments: 4,
            view: "above".into(),
            camera: super::super::CameraRecord { position: [0.0; 3], yaw_deg: 0.0, pitch_deg: 0.0 },
            ratio: brute / gpu,
            cull_share: 0.05,
            diff: Some(DiffRecord { block: 8, mean_percent: 1.25, p99_percent: 4.5, max_percent: 9.0 }),
            variants: vec![variant("brute-force", brute, 1000), variant("gpu-driven", gpu, 250)],
        };
        let mut header = crate::harness::bench::document::fixtures::header();
        header.resolution = [64, 48];
        LodDocument {
            header,
            options: LodOptionsRecord {
                rows: 2,
                size: [64, 48],
                warmup: 0,
                frames: 2,
                segments: 4,
                simulation_time_s: 0.0,
                diff_block: 8,
            },
            warmup: 0,
            frames_per_variant: 2,
            rows: vec![row("stored, \"above\"", 40.0, 10.0), row("stored, edge", 30.0, 20.0)],
        }
    }

    #[test]
    fn the_table_and_the_csv_carry_each_row() {
        let doc = doc();
        let t = table(&doc);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[1].contains("  4.00 ") && lines[1].contains("  5.0%") && lines[1].contains("  1.25 "), "{t}");
        assert!(lines[2].contains("  1.50 ") && lines[2].contains(" 250 "), "{t}");
        let csv = csv(&doc);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 1 + 2 * 2 * 2, "rows x variants x frames:\n{csv}");
        // A quoted label keeps its comma; brute force has no difference to itself.
        assert!(
            lines[1].starts_with("\"stored, \"\"above\"\"\",stored,1000,4,above,brute-force,0,40.0,0.5,1000,8000,,")
        );
        assert!(lines[3].ends_with("gpu-driven,0,10.0,0.5,250,2000,1.25,4.5"), "{}", lines[3]);
    }
}
