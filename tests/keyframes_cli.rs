//! `meadow keyframes`: the thesis' compression example reproduced exactly, the export, and the
//! pose-error section (issue 13, item 3) against the library's pose selection and direct solve.

use meadow::keyframes::pose::{self, BladeModel};
use meadow::keyframes::pose_error::{sample_forces, SAMPLES, SEED};
use meadow::keyframes::{KeyframeLayout, KeyframeTable, Smoothing};

mod support;

#[test]
fn report_reproduces_the_thesis_example_and_export_writes_the_texture() {
    let dir = support::scratch("keyframes-cli");
    let png = dir.join("keyframes.png");
    let output = support::meadow()
        .args(["keyframes", "--poses", "1000", "--segments", "4", "--report", "--export"])
        .arg(&png)
        .output()
        .expect("run meadow");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", support::transcript(&output));
    let thesis: Vec<&str> = stdout.lines().skip_while(|l| !l.starts_with("thesis blade")).take(6).collect();
    assert!(thesis[0].contains("32 vertices") && thesis[0].contains("15 records"), "{stdout}");
    assert!(thesis[1].contains(" 3072000 bits"), "{stdout}");
    assert!(thesis[4].contains(" 720000 bits"), "{stdout}");
    assert!(thesis[5].contains(" 180000 bits"), "{stdout}");
    assert!(stdout.contains("meadow blade: 4 segments, 10 vertices"), "{stdout}");
    assert!(stdout.contains("curve keyframes (3 control points") && stdout.contains("at 16 segments"), "{stdout}");
    let picture = image::open(&png).expect("exported PNG");
    assert_eq!((picture.width(), picture.height()), (4, 250));
}

/// The numbers of one printed pose-error row: poses, stored, magnitudes, angles, then per
/// smoothing mean and max (% of blade length), then the twist maxima.
fn pose_error_row(stdout: &str, poses: u32) -> Vec<f32> {
    let line = stdout
        .lines()
        .skip_while(|l| !l.starts_with("pose error against a direct solve"))
        .find(|l| l.split_whitespace().next() == Some(poses.to_string().as_str()))
        .unwrap_or_else(|| panic!("no pose-error row for {poses} poses:\n{stdout}"));
    line.split(|c: char| c.is_whitespace() || "()|x".contains(c)).filter_map(|t| t.parse().ok()).collect()
}

#[test]
fn report_prints_the_pose_error_of_the_renderers_tables_whatever_poses() {
    let output = support::meadow()
        .args(["keyframes", "--poses", "64", "--segments", "2", "--report"])
        .output()
        .expect("run meadow");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", support::transcript(&output));
    assert!(stdout.contains("pose error against a direct solve (2 segments, 1024 forces"), "{stdout}");
    // The three counts of the issue, not --poses, a quarter of each stored.
    for (poses, stored) in [(250, 65.0), (1000, 250.0), (4000, 1000.0)] {
        assert_eq!(pose_error_row(&stdout, poses)[1], stored, "{stdout}");
    }
    assert!(!stdout.lines().any(|l| l.trim_start().starts_with("64 ")), "{stdout}");
    assert_eq!(stdout.matches("keep the max error under 0.5 %").count(), 2, "{stdout}");
    assert!(stdout.contains("nearest: none of 250 / 1000 / 4000 poses keeps the max error under 0.5 %"), "{stdout}");

    // The 4000-pose SLERP entry recomputed: the renderer's table, its CPU selection, direct solves.
    let row = pose_error_row(&stdout, 4000);
    assert_eq!(row.len(), 13, "poses, stored, mag, ang, 3 x (mean, max), 3 twists: {row:?}");
    let model = BladeModel::new(2);
    let table = KeyframeTable::generate(&model, KeyframeLayout::for_poses(4000));
    let errors: Vec<f32> = sample_forces(SEED, SAMPLES)
        .into_iter()
        .map(|(fx, fz)| {
            let (from_table, direct) = (table.pose_for(fx, fz, Smoothing::Slerp), pose::solve(&model, fx, fz));
            (0..=2).map(|l| 100.0 * (from_table.backbone[l] - direct.backbone[l]).length()).fold(0.0, f32::max)
        })
        .collect();
    let mean = errors.iter().sum::<f32>() / errors.len() as f32;
    let max = errors.iter().copied().fold(0.0, f32::max);
    // Printed with 3 decimals.
    assert!((row[8] - mean).abs() <= 6e-4 && (row[9] - max).abs() <= 6e-4, "printed {row:?}, recomputed {mean} {max}");
}
