//! What `meadow bench --preset lod` makes of its JSON document: the table, the tidy CSV and the
//! chart, written whole or not at all.

use std::path::Path;

use serde_json::Value;

use super::VARIANTS;
use crate::app::write_text;
use crate::error::Result;
use crate::harness::plot::BarPanel;

/// The variant `name` of a row.
fn variant<'a>(row: &'a Value, name: &str) -> &'a Value {
    row["variants"].as_array().and_then(|vs| vs.iter().find(|v| v["variant"] == name)).unwrap_or(&Value::Null)
}

/// Median GPU ms of variant `name` of a row (0 when absent).
fn median(row: &Value, name: &str) -> f64 {
    variant(row, name)["gpu_ms"]["median"].as_f64().unwrap_or(0.0)
}

/// The table printed after a run: per row, both medians, their ratio, the cull share, what the
/// GPU-driven path considered and drew, and the box-filtered difference.
pub fn table(doc: &Value) -> String {
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
    for row in doc["rows"].as_array().into_iter().flatten() {
        let gpu = variant(row, VARIANTS[1]);
        let number = |v: &Value| v.as_u64().unwrap_or(0);
        let percent = |v: &Value| v.as_f64().map_or("-".to_string(), |p| format!("{p:.2}"));
        out.push_str(&format!(
            "{:<20} {:>8} {:<8}| {:>9.2} {:>9.2} {:>6.2} {:>5.1}% | {:>10} {:>9} {:>10} {:>10} | {:>6} {:>6} {:>6}\n",
            row["label"].as_str().unwrap_or(""),
            number(&row["blades"]),
            row["view"].as_str().unwrap_or(""),
            median(row, VARIANTS[0]),
            median(row, VARIANTS[1]),
            row["ratio"].as_f64().unwrap_or(0.0),
            100.0 * row["cull_share"].as_f64().unwrap_or(0.0),
            number(&gpu["counts"]["considered"]),
            number(&gpu["drawn_blades"]),
            number(&gpu["blade_triangles"]),
            number(&variant(row, VARIANTS[0])["blade_triangles"]),
            percent(&row["diff"]["mean_percent"]),
            percent(&row["diff"]["p99_percent"]),
            percent(&row["diff"]["max_percent"]),
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
pub fn csv(doc: &Value) -> String {
    let mut out = String::from(
        "label,field,blades,segments,view,variant,frame,gpu_ms,cull_ms,drawn_blades,blade_triangles,\
         diff_mean_percent,diff_p99_percent\n",
    );
    for row in doc["rows"].as_array().into_iter().flatten() {
        for v in row["variants"].as_array().into_iter().flatten() {
            let reference = v["variant"] == VARIANTS[0];
            // Empty for brute force (no difference to itself) and for a row of two scenes.
            let diff = |key: &str| match row["diff"][key].as_f64() {
                Some(p) if !reference => p.to_string(),
                _ => String::new(),
            };
            for (i, f) in v["frames"].as_array().into_iter().flatten().enumerate() {
                out.push_str(&format!(
                    "\"{}\",{},{},{},{},{},{},{},{},{},{},{},{}\n",
                    row["label"].as_str().unwrap_or("").replace('"', "\"\""),
                    row["field"]["kind"].as_str().unwrap_or(""),
                    row["blades"],
                    row["segments"],
                    row["view"].as_str().unwrap_or(""),
                    v["variant"].as_str().unwrap_or(""),
                    i,
                    f["gpu_ms"],
                    f["cull_ms"],
                    v["drawn_blades"],
                    v["blade_triangles"],
                    diff("mean_percent"),
                    diff("p99_percent"),
                ));
            }
        }
    }
    out
}

/// Write lod.json, lod.csv and lod.png into `dir`.
/// The files of a run, one set: the report, its table, its chart.
pub const FILES: [&str; 3] = ["lod.json", "lod.csv", "lod.png"];

pub fn write(doc: &Value, dir: &Path) -> Result<()> {
    let text = serde_json::to_string_pretty(doc).expect("a JSON value serialises");
    let [json, table, chart] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(doc))?;
    plot(doc, &dir.join(chart))
}

/// `lod.png`, three bar charts with a bar group per row: the median frame time of brute force
/// and GPU-driven, the speed-up (brute / GPU-driven), and the box-filtered difference (mean and
/// 99th-percentile block) of the rows that have one (not a row of two scenes).
pub fn plot(doc: &Value, path: &Path) -> Result<()> {
    let rows = doc["rows"].as_array().map_or(0, Vec::len) as u32;
    let height = (180 + 90 * rows).clamp(420, 4000);
    let title = format!(
        "meadow bench --preset lod: {} at {}x{}, {} segments",
        doc["device"].as_str().unwrap_or("?"),
        doc["resolution"][0],
        doc["resolution"][1],
        doc["options"]["segments"]
    );
    crate::harness::plot::bar_panels(path, (1680, height), &title, &panels(doc), 3)
}

/// The panels of `lod.png`.
fn panels(doc: &Value) -> Vec<BarPanel> {
    let rows: Vec<&Value> = doc["rows"].as_array().into_iter().flatten().collect();
    let labels: Vec<String> = rows.iter().map(|r| r["label"].as_str().unwrap_or("").to_string()).collect();
    let values = |f: &dyn Fn(&Value) -> f64| -> Vec<f64> { rows.iter().map(|r| f(r)).collect() };
    let number = |v: &Value| v.as_f64().unwrap_or(0.0);
    let compared: Vec<&Value> = rows.iter().copied().filter(|r| r["diff"].is_object()).collect();
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
        panel("speed-up", "brute force / GPU-driven", vec![(String::new(), values(&|r| number(&r["ratio"])))]),
    ];
    // Only the rows with a difference: a row of two scenes (the unbounded field) has none.
    if !compared.is_empty() {
        panels.push(BarPanel {
            title: "difference to brute force".into(),
            value_label: "% of full scale, 8x8 blocks".into(),
            categories: compared.iter().map(|r| r["label"].as_str().unwrap_or("").to_string()).collect(),
            groups: vec![
                ("mean".into(), compared.iter().map(|r| number(&r["diff"]["mean_percent"])).collect()),
                ("p99 block".into(), compared.iter().map(|r| number(&r["diff"]["p99_percent"])).collect()),
            ],
        });
    }
    panels
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn the_difference_panel_has_only_the_rows_with_a_difference() {
        let mut doc = doc();
        let titles = |doc: &Value| panels(doc).iter().map(|p| p.title.clone()).collect::<Vec<_>>();
        assert_eq!(titles(&doc), ["frame time", "speed-up", "difference to brute force"]);
        // A row of two scenes (an unbounded field against the stored reference) has none.
        doc["rows"][1]["diff"] = Value::Null;
        let all = panels(&doc);
        assert_eq!(all[0].categories.len(), 2);
        assert_eq!(all[2].categories, ["stored, \"above\""]);
        assert_eq!(all[2].groups[0].1, [1.25]);
        doc["rows"][0]["diff"] = Value::Null;
        assert_eq!(titles(&doc), ["frame time", "speed-up"], "no difference, no panel");
    }

    fn doc() -> Value {
        let variant = |name: &str, ms: f64, drawn: u64| {
            json!({"variant": name, "gpu_ms": {"median": ms}, "drawn_blades": drawn, "blade_triangles": 8 * drawn,
                   "counts": {"considered": 1000}, "frames": [{"gpu_ms": ms, "cull_ms": 0.5}, {"gpu_ms": ms, "cull_ms": 0.5}]})
        };
        let row = |label: &str, brute: f64, gpu: f64| {
            json!({"label": label, "field": {"kind": "stored"}, "blades": 1000, "segments": 4, "view": "above",
                   "ratio": brute / gpu, "cull_share": 0.05,
                   "diff": {"mean_percent": 1.25, "p99_percent": 4.5, "max_percent": 9.0},
                   "variants": [variant("brute-force", brute, 1000), variant("gpu-driven", gpu, 250)]})
        };
        json!({"device": "test", "resolution": [64, 48], "options": {"segments": 4},
               "rows": [row("stored, \"above\"", 40.0, 10.0), row("stored, edge", 30.0, 20.0)]})
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
