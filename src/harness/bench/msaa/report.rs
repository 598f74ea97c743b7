//! What `meadow bench --preset msaa` makes of its run: the table, the tidy CSV and the far-field
//! crop of every variant side by side, written whole or not at all.

use std::path::Path;

use super::document::{MsaaDocument, MsaaRow, MsaaVariant};
use super::MsaaRun;
use crate::app::output::{encode_png, write_atomically};
use crate::app::write_text;
use crate::error::Result;
use crate::harness::document::{number, to_json};

/// Magnification of the far-field crops.
const CROP_SCALE: u32 = 3;

/// The rows' variants, flattened: (row, variant).
fn entries(doc: &MsaaDocument) -> impl Iterator<Item = (&MsaaRow, &MsaaVariant)> {
    doc.rows.iter().flat_map(|row| row.variants.iter().map(move |variant| (row, variant)))
}

/// The table printed after a run: per row and variant, the median GPU time and its ratio to no
/// MSAA, the mean frame-to-frame change of the pan and its ratio to no MSAA.
pub fn table(doc: &MsaaDocument) -> String {
    let mut out = format!(
        "{:<38} {:<24} | {:>9} {:>6} | {:>9} {:>7}\n",
        "row", "variant", "GPU ms", "cost", "change %", "change"
    );
    for (row, v) in entries(doc) {
        out.push_str(&format!(
            "{:<38} {:<24} | {:>9.2} {:>5.2}x | {:>9.4} {:>6.2}x\n",
            row.label, v.variant, v.gpu_ms.median, v.cost_ratio, v.change_percent, v.change_ratio,
        ));
    }
    out
}

/// Tidy CSV: one line per row and variant.
pub fn csv(doc: &MsaaDocument) -> String {
    let mut out =
        String::from("row,variant,samples,alpha_to_coverage,gpu_ms_median,cost_ratio,change_percent,change_ratio\n");
    for (row, v) in entries(doc) {
        out.push_str(&format!(
            "\"{}\",{},{},{},{},{},{},{}\n",
            row.label.replace('"', "\"\""),
            v.variant,
            v.samples,
            v.alpha_to_coverage,
            number(v.gpu_ms.median),
            number(v.cost_ratio),
            number(v.change_percent),
            number(v.change_ratio),
        ));
    }
    out
}

/// `msaa.json`, `msaa.csv` and `msaa-far-field.png` into `dir`.
/// The files of a run, one set: the report, its table, the far-field pictures.
pub const FILES: [&str; 3] = ["msaa.json", "msaa.csv", "msaa-far-field.png"];

pub fn write(run: &MsaaRun, dir: &Path) -> Result<()> {
    let text = to_json(&run.doc);
    let [json, table, picture] = FILES;
    write_text(&dir.join(json), &text)?;
    write_text(&dir.join(table), &csv(&run.doc))?;
    let [w, h] = run.doc.header.resolution;
    write_atomically(&dir.join(picture), &encode_png(&far_field(&run.pictures, w, h))?)
}

/// The far field of every picture (a row of variants per row), magnified, with 4-pixel white
/// gaps: the hill's outline from the default camera, an eighth of the width by a ninth of the
/// height around it.
pub fn far_field(pictures: &[Vec<Vec<u8>>], width: u32, height: u32) -> image::RgbImage {
    let (x0, y0, cw, ch) = (width * 7 / 16, height * 3 / 8, width / 8, height / 9);
    let (tw, th) = (cw * CROP_SCALE, ch * CROP_SCALE);
    let columns = pictures.iter().map(Vec::len).max().unwrap_or(0) as u32;
    let gap = 4;
    let (out_w, out_h) = (columns * (tw + gap) - gap.min(columns * gap), pictures.len() as u32 * (th + gap));
    let mut out = image::RgbImage::from_pixel(out_w.max(1), out_h.max(1), image::Rgb([255, 255, 255]));
    for (r, row) in pictures.iter().enumerate() {
        for (c, picture) in row.iter().enumerate() {
            if picture.len() != (width * height * 3) as usize {
                continue;
            }
            for y in 0..th {
                for x in 0..tw {
                    let (sx, sy) = (x0 + x / CROP_SCALE, y0 + y / CROP_SCALE);
                    let i = ((sy * width + sx) * 3) as usize;
                    let pixel = image::Rgb([picture[i], picture[i + 1], picture[i + 2]]);
                    out.put_pixel(c as u32 * (tw + gap) + x, r as u32 * (th + gap) + y, pixel);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::MsaaOptionsRecord;
    use super::*;

    fn doc() -> MsaaDocument {
        let variant = |name: &str, ms: f64, change: f64| MsaaVariant {
            variant: name.into(),
            samples: 4,
            alpha_to_coverage: true,
            gpu_ms: crate::harness::document::Summary::of(&[ms]),
            frames_ms: vec![ms],
            cost_ratio: ms / 100.0,
            change_percent: change,
            changes_percent: vec![change],
            change_ratio: change / 0.5,
        };
        let row = MsaaRow {
            label: "default, \"a\"".into(),
            culled: true,
            blades: 10,
            variants: vec![variant("no MSAA", 100.0, 0.5), variant("4x alpha to coverage", 180.0, 0.3)],
        };
        let options = MsaaOptionsRecord {
            blades: 10,
            segments: 4,
            size: [64, 72],
            warmup: 0,
            frames: 1,
            pan_frames: 2,
            pan_deg_per_frame: 0.05,
            simulation_time_s: 0.0,
            diff_block: 8,
            samples: 4,
        };
        let mut header = crate::harness::bench::document::fixtures::header();
        header.resolution = [64, 72];
        MsaaDocument { header, options, rows: vec![row] }
    }

    #[test]
    fn the_table_and_the_csv_carry_each_variant() {
        let doc = doc();
        let t = table(&doc);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 3, "{t}");
        assert!(lines[2].contains("180.00  1.80x") && lines[2].contains("0.3000   0.60x"), "{t}");
        let csv = csv(&doc);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3, "{csv}");
        assert_eq!(lines[2], "\"default, \"\"a\"\"\",4x alpha to coverage,4,true,180.0,1.8,0.3,0.6");
    }

    #[test]
    fn the_crop_magnifies_the_far_field_of_each_picture() {
        let (w, h) = (64u32, 72u32);
        let mut picture = vec![0u8; (w * h * 3) as usize];
        // The crop's top-left source pixel is (28, 27): mark it.
        let i = ((27 * w + 28) * 3) as usize;
        picture[i..i + 3].copy_from_slice(&[200, 100, 50]);
        let out = far_field(&[vec![picture.clone(), picture]], w, h);
        let (tw, th) = (8 * CROP_SCALE, 8 * CROP_SCALE);
        assert_eq!((out.width(), out.height()), (2 * tw + 4, th + 4));
        for (x, y) in [(0, 0), (CROP_SCALE - 1, CROP_SCALE - 1), (tw + 4, 0)] {
            assert_eq!(out.get_pixel(x, y).0, [200, 100, 50], "({x}, {y})");
        }
        assert_eq!(out.get_pixel(CROP_SCALE, 0).0, [0, 0, 0]);
        assert_eq!(out.get_pixel(tw, 0).0, [255, 255, 255], "the gap");
    }
}
