//! `meadow keyframes`: generate the keyframe table, report its compression figures (thesis 3.3),
//! the measured encoding errors (4.4) and how well the curve representation matches the vertex
//! one, the pose error of the table against a direct solve, and export the table as a 16-bit
//! picture. CPU only.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::output::check_output;
use crate::error::Result;
use crate::keyframes::compression::{BladeGeometry, CompressionReport};
use crate::keyframes::encoding::{self, Encoding};
use crate::keyframes::pose_error::PoseErrorReport;
use crate::keyframes::{BladeModel, KeyframeLayout, KeyframeTable};

/// `meadow keyframes` options.
#[derive(Clone, Debug)]
pub struct KeyframeOptions {
    /// Poses over the full circle.
    pub poses: u32,
    /// Segments of meadow's blade.
    pub segments: u32,
    /// Print the compression figures.
    pub report: bool,
    /// Write the keyframe texture (unorm16) as a 16-bit RGBA PNG.
    pub export: Option<PathBuf>,
}

/// `meadow keyframes`: generate the table, print its compression figures (thesis 3.3), the
/// measured encoding errors (4.4) and the pose error against a direct solve, optionally export
/// the texture as a picture. CPU only.
pub fn keyframes(options: &KeyframeOptions) -> Result<String> {
    if let Some(path) = &options.export {
        check_output(path, "--export")?;
    }
    let started = Instant::now();
    let layout = KeyframeLayout::for_poses(options.poses);
    let table = KeyframeTable::generate(&BladeModel::new(options.segments), layout);
    let generation_ms = started.elapsed().as_secs_f64() * 1e3;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "keyframes: {} x {} segments generated in {generation_ms:.1} ms: {} magnitudes x {} angles = {} stored, {} represented with the mirrors",
        options.poses,
        options.segments,
        layout.magnitudes,
        layout.angles,
        layout.stored(),
        layout.represented()
    );
    if options.report {
        let _ = write!(out, "{}", CompressionReport::new(BladeGeometry::thesis(8), options.poses));
        let _ = write!(out, "{}", CompressionReport::new(BladeGeometry::meadow(options.segments), options.poses));
        encoding_errors(&mut out);
        curve_against_vertex(&mut out, layout);
        let started = Instant::now();
        let pose_error = PoseErrorReport::measure(options.segments);
        let _ = write!(out, "{pose_error}");
        let _ = writeln!(out, "  (measured in {:.0} ms)", started.elapsed().as_secs_f64() * 1e3);
    }
    if let Some(path) = &options.export {
        export(&mut out, &table, path)?;
    }
    Ok(out)
}

/// The measured round-trip errors of every keyframe encoding over [-1, 1], against the thesis'.
fn encoding_errors(out: &mut String) {
    let e8 = encoding::max_error(200_001, |x| encoding::d1(encoding::e1(x)));
    let e16 = encoding::max_error(200_001, |x| encoding::decode_rgba8x2(encoding::e1(x), encoding::e2(x)));
    let u16e = encoding::max_error(200_001, |x| encoding::decode_unorm16(encoding::encode_unorm16(x)));
    let m1 = encoding::max_error(200_001, |x| encoding::thesis_extract1(encoding::thesis_merge(x, 0.3)));
    let m2 = encoding::max_error(200_001, |x| encoding::thesis_extract2(encoding::thesis_merge(-0.7, x)));
    let snorm = encoding::max_error(200_001, |x| encoding::unpack_snorm2x16(encoding::pack_snorm2x16(0.5, x)).1);
    let _ = writeln!(out, "measured max round-trip errors over [-1, 1] (thesis: d8 ~ 7.9125e-3, d16 ~ 3.05175e-5):");
    let _ = writeln!(out, "  one byte (e1/d1)                   {e8:.4e}");
    let _ = writeln!(out, "  two bytes rgba8x2 (e1,e2 / d1+d2)  {e16:.4e}");
    let _ = writeln!(out, "  unorm16                            {u16e:.4e}");
    let _ = writeln!(out, "  uniform merge/extract1 in f32      {m1:.4e}");
    // Worst case over both values in [-1, 0.9], away from the wrap-around near 1: there the
    // rounding of the merged float (ulp up to 2^-22) carries f2 into f1 and f2 reads as -1.
    let m2_inner = (0..=40)
        .map(|j| -1.0 + 1.9 * j as f32 / 40.0)
        .flat_map(|f1| {
            (0..5001).map(move |i| {
                let x = -1.0 + 1.9 * i as f32 / 5000.0;
                (encoding::thesis_extract2(encoding::thesis_merge(f1, x)) - x).abs()
            })
        })
        .fold(0.0f32, f32::max);
    let _ = writeln!(
        out,
        "  uniform merge/extract2 in f32      {m2:.4e}  (wraps near 1: the merged float's rounding carries f2 into f1)"
    );
    let _ = writeln!(
        out,
        "  uniform merge/extract2 on [-1, 0.9] {m2_inner:.4e}  (not 16-bit: f32 keeps 24 significant bits)"
    );
    let _ = writeln!(out, "  exact snorm16x2 packing            {snorm:.4e}");
}

/// The curve representation (3 records per pose whatever the segment count) against vertex
/// keyframes at 4, 8 and 16 segments: table size and the largest distance between the two.
fn curve_against_vertex(out: &mut String, layout: KeyframeLayout) {
    // The curve representation: 3 records per pose whatever the segment count.
    let curve = KeyframeTable::generate_curve(layout);
    let _ = writeln!(
        out,
        "curve keyframes (3 control points, 4 x 16 bit each, a quarter stored): {} bits per table for any segment count",
        u64::from(layout.stored()) * 3 * 4 * 16
    );
    let fine = KeyframeTable::generate(&BladeModel::new(crate::keyframes::table::CURVE_FIT_SEGMENTS), layout);
    for s in [4u32, 8, 16] {
        let vertex = KeyframeTable::generate(&BladeModel::new(s), layout);
        let mut worst = 0.0f32;
        let mut chain_worst = 0.0f32;
        for row in 0..layout.stored() {
            let control: Vec<glam::Vec3> = (1..=3)
                .map(|r| {
                    let k = curve.keyframe(row, r);
                    curve.straight(r) + glam::Vec3::new(k[0], k[1], k[2])
                })
                .collect();
            let cp = [glam::Vec3::ZERO, control[0], control[1], control[2]];
            for level in 1..=s {
                let k = vertex.keyframe(row, level);
                let chain = vertex.straight(level) + glam::Vec3::new(k[0], k[1], k[2]);
                let on_curve = crate::scene::bezier::point(&cp, level as f32 / s as f32);
                worst = worst.max((on_curve - chain).length());
                // The same point of the 16-segment chain the curve was fitted to.
                let fine_level = level * crate::keyframes::table::CURVE_FIT_SEGMENTS / s;
                let f = fine.keyframe(row, fine_level);
                let fine_point = fine.straight(fine_level) + glam::Vec3::new(f[0], f[1], f[2]);
                chain_worst = chain_worst.max((fine_point - chain).length());
            }
        }
        let vertex_bits = u64::from(layout.stored()) * u64::from(s) * 4 * 16;
        let _ = writeln!(
            out,
            "  vs vertex keyframes at {s:>2} segments ({vertex_bits:>7} bits): largest level error {:.2} % of the blade length; that chain itself lies up to {:.2} % from the 16-segment chain the curve is fitted to",
            100.0 * worst,
            100.0 * chain_worst
        );
    }
}

/// Write the table as unorm16 texels into a 16-bit RGBA PNG at `path` (atomically).
fn export(out: &mut String, table: &KeyframeTable, path: &Path) -> Result<()> {
    let (width, height, bytes) = encoding::texture_texels(table, Encoding::Unorm16);
    let words: Vec<u16> = bytes.chunks_exact(2).map(|b| u16::from_le_bytes([b[0], b[1]])).collect();
    let image =
        image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(width, height, words).expect("texels match the size");
    super::output::write_atomically(path, &super::output::encode_png(&image)?)?;
    let _ = writeln!(out, "wrote {} ({width}x{height}, RGBA16: displacement xyz, twist / (pi/2))", path.display());
    Ok(())
}
