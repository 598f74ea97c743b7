//! What `meadow bench --preset animations` makes of its run: the table printed, the tidy CSV and
//! the JSON, written whole or not at all.

use std::path::Path;

use super::document::{AnimationsDocument, AnimationsRow, AnimationsVariant};
use crate::app::write_text;
use crate::error::Result;
use crate::harness::document::{number, to_json};

/// The files of a run: the report and its table.
pub const FILES: [&str; 2] = ["animations.json", "animations.csv"];

/// The rows' variants, flattened: (row, variant).
fn entries(doc: &AnimationsDocument) -> impl Iterator<Item = (&AnimationsRow, &AnimationsVariant)> {
    doc.rows.iter().flat_map(|row| row.variants.iter().map(move |variant| (row, variant)))
}

/// The table printed after a run: per row and response, the median GPU time, its ratio to static,
/// and the response's own passes per step.
pub fn table(doc: &AnimationsDocument) -> String {
    let mut out = format!(
        "{:<30} {:<16} {:<9} | {:>9} {:>8} | {:>11} {:>6}\n",
        "row", "animation", "wind", "GPU ms", "/static", "ms / step", "steps"
    );
    for (row, v) in entries(doc) {
        out.push_str(&format!(
            "{:<30} {:<16} {:<9} | {:>9.2} {:>7.3}x | {:>11.3} {:>6}\n",
            row.label, v.animation, v.wind_field, v.gpu_ms.median, v.ratio_to_static, v.ms_per_step, v.steps_per_frame,
        ));
    }
    out
}

/// Tidy CSV: one line per row and response.
pub fn csv(doc: &AnimationsDocument) -> String {
    let mut out = String::from(
        "row,culled,blades,segments,wind_field,animation,response,gpu_ms_median,ratio_to_static,response_ms_median,steps_per_frame,ms_per_step\n",
    );
    for (row, v) in entries(doc) {
        out.push_str(&format!(
            "\"{}\",{},{},{},{},{},\"{}\",{},{},{},{},{}\n",
            row.label.replace('"', "\"\""),
            row.culled,
            row.blades,
            row.segments,
            v.wind_field,
            v.animation,
            v.response,
            number(v.gpu_ms.median),
            number(v.ratio_to_static),
            number(v.response_ms.median),
            v.steps_per_frame,
            number(v.ms_per_step),
        ));
    }
    out
}

/// `animations.json` and `animations.csv` into `dir`.
pub fn write(doc: &AnimationsDocument, dir: &Path) -> Result<()> {
    let [json, table] = FILES;
    write_text(&dir.join(json), &to_json(doc))?;
    write_text(&dir.join(table), &csv(doc))
}
