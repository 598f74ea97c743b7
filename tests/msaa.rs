//! `--msaa N`: every supported count renders validation-clean, an unsupported one is refused with
//! the supported list, the resolve keeps the target's encoding, the depth pyramid stays
//! conservative, and alpha to coverage brings the far field closer to a supersampled reference
//! than the alpha test alone.

mod support;

use meadow::app::{with_device, GpuOptions};
use meadow::imagediff::{box_filtered_difference, downsample_2x_srgb};
use meadow::render::msaa;
use meadow::vk::DeviceSelector;
use support::{render, scratch, Picture};

fn supported() -> Vec<u32> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (counts, messages) = with_device(&options, false, |device| Ok(msaa::supported_counts(device)));
    assert_eq!(messages, Some(0));
    counts.expect("device")
}

/// The cull's line of a render's output.
fn cull_line(output: &std::process::Output) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).to_string();
    stdout.lines().find(|l| l.starts_with("cull:")).expect("a cull line").to_string()
}

/// The "N not occluded" figure of a cull line.
fn not_occluded(line: &str) -> u64 {
    let before = line.split(" not occluded").next().expect("figure");
    before.rsplit(' ').next().expect("number").parse().expect("integer")
}

#[test]
fn every_supported_count_renders_and_others_are_refused() {
    let counts = supported();
    assert!(counts.contains(&1) && counts.len() > 1, "lavapipe multisamples: {counts:?}");
    let dir = scratch("msaa-counts");
    let mut sky = Vec::new();
    let mut occluded = Vec::new();
    for &n in &counts {
        let samples = n.to_string();
        for brute in [false, true] {
            let mut args = vec!["--blades", "8000", "--size", "160x96", "--msaa", &samples];
            if brute {
                args.push("--brute-force");
            }
            let out = dir.join(format!("m{n}-{brute}.png"));
            let output = render(&args, &out);
            let picture = Picture::load(&out);
            if !brute {
                occluded.push(not_occluded(&cull_line(&output)));
                // The top row is sky: the resolve encodes it as the single-sampled path does.
                sky.push((0..picture.width).map(|x| picture.pixel(x, 0)).collect::<Vec<_>>());
            }
        }
    }
    for (row, &n) in sky.iter().zip(&counts) {
        for (a, b) in row.iter().zip(&sky[0]) {
            assert!(a.iter().zip(b).all(|(a, b)| a.abs_diff(*b) <= 1), "sky at {n} samples: {a:?} against {b:?}");
        }
    }
    // The pyramid takes each pixel's farthest sample: never more blades occluded than with one.
    for (&drawn, &n) in occluded.iter().zip(&counts) {
        assert!(drawn >= occluded[0], "{n} samples keep {drawn} blades, 1 sample {}", occluded[0]);
    }
    for bad in [3u32, 128, 1 << 20].into_iter().chain((2..=64).map(|b| 1u32 << (b % 7)).filter(|n| !counts.contains(n)))
    {
        let output = support::meadow()
            .args(["render", "--blades", "1000", "--msaa", &bad.to_string(), "--out"])
            .arg(dir.join("bad.png"))
            .output()
            .expect("run meadow");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "--msaa {bad}: {stderr}");
        let list: Vec<String> = counts.iter().map(u32::to_string).collect();
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
        assert!(
            stderr.starts_with("error: --msaa") && stderr.contains(&format!("supported: {}", list.join(", "))),
            "{stderr}"
        );
        assert!(!dir.join("bad.png").exists(), "--msaa {bad} wrote a picture");
    }
}

/// The far-field band of a `width`×`height` picture from the default camera: six 8-pixel block
/// rows from 40 % of the height (at 320×180, just below the hill's outline), where the blades are
/// a pixel wide or less.
fn far_band(rgb: &[u8], width: u32, height: u32) -> (Vec<u8>, u32) {
    let top = height * 2 / 5 / 8 * 8;
    let rows = 6 * 8;
    let row = 3 * width as usize;
    (rgb[top as usize * row..(top + rows) as usize * row].to_vec(), rows)
}

#[test]
fn alpha_to_coverage_is_closer_to_a_supersampled_reference() {
    let dir = scratch("msaa-a2c");
    let common = ["--brute-force", "--blades", "60000", "--seed", "3", "--wind", "0,0", "--msaa", "4"];
    let shot = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let args: Vec<&str> = common.iter().chain(extra).copied().collect();
        render(&args, &out);
        Picture::load(&out)
    };
    let (w, h) = (320, 180);
    let coverage = shot("a2c.png", &["--size", "320x180"]);
    let alpha_test = shot("alpha-test.png", &["--size", "320x180", "--no-alpha-to-coverage"]);
    // The reference: twice the resolution with 4 samples, each sample tested against the outline
    // (16 outline tests per pixel), downsampled in linear light. (An alpha-tested reference would
    // test the outline once per pixel of the larger picture and keep every sample of the quad:
    // the alpha test's own bias, at a finer scale.)
    let big = shot("reference.png", &["--size", "640x360"]);
    let reference = downsample_2x_srgb(&big.rgb, 640, 360);
    let (reference, rows) = far_band(&reference, w, h);
    let error = |p: &Picture| {
        let (band, _) = far_band(&p.rgb, w, h);
        box_filtered_difference(&band, &reference, w, rows, 8).mean_percent
    };
    let (with, without) = (error(&coverage), error(&alpha_test));
    eprintln!("far field against the reference: alpha to coverage {with:.3} %, alpha test {without:.3} %");
    assert!(with < without, "alpha to coverage {with:.3} % is not closer than the alpha test {without:.3} %");
    // The far field is drawn, not sky: the comparison has something to compare.
    let (band, _) = far_band(&coverage.rgb, w, h);
    let sky = band.chunks_exact(3).filter(|p| p[2] > 200).count();
    assert!(sky < band.len() / 3 / 4, "{sky} sky pixels in the far-field band");
}

#[test]
fn the_msaa_preset_measures_cost_and_a_steadier_pan() {
    let dir = scratch("bench-msaa");
    let output = support::meadow()
        .args(["bench", "--preset", "msaa", "--validation", "--device", support::DEVICE, "--blades", "8000"])
        .args(["--size", "160x96", "--frames", "1", "--warmup", "0", "--out"])
        .arg(&dir)
        .output()
        .expect("run meadow bench --preset msaa");
    support::assert_clean(&output);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("msaa.json")).expect("msaa.json")).expect("JSON");
    assert_eq!(doc["kind"], "msaa");
    let rows = doc["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 2);
    for row in rows {
        let variants = row["variants"].as_array().expect("variants");
        assert_eq!(variants.len(), 3);
        assert_eq!(variants[0]["cost_ratio"], 1.0);
        for v in variants {
            assert!(v["gpu_ms"]["median"].as_f64().expect("ms") > 0.0, "{v}");
            // The pan's 12 frames give 11 changes, each a measured, non-zero figure.
            let changes = v["changes_percent"].as_array().expect("changes");
            assert_eq!(changes.len(), 11);
            assert!(changes.iter().all(|c| c.as_f64().expect("number") > 0.0), "{v}");
        }
        // Multisampling steadies the pan (the pictures are deterministic, so is this).
        for v in &variants[1..] {
            let ratio = v["change_ratio"].as_f64().expect("ratio");
            assert!(ratio < 0.9, "{}: {}x the single-sampled change", row["label"], ratio);
        }
    }
    let csv = std::fs::read_to_string(dir.join("msaa.csv")).expect("msaa.csv");
    assert_eq!(csv.lines().count(), 1 + 2 * 3, "{csv}");
    let crop = image::open(dir.join("msaa-far-field.png")).expect("the crop decodes");
    assert!(crop.width() > 3 * 160 / 8 * 3 && crop.height() > 2 * 96 / 9 * 3, "{}x{}", crop.width(), crop.height());
}

#[test]
fn every_submission_strategy_draws_multisampled() {
    // Secondary command buffers inherit the attachments' sample count and depth format; a
    // pre-recorded frame replays into the same multisampled images.
    let dir = scratch("msaa-submission");
    for strategy in ["instanced", "per-cluster", "indirect", "mdi", "secondary", "prerecorded"] {
        let args = ["--brute-force", "--blades", "3000", "--size", "160x96", "--msaa", "4", "--frames", "2"];
        // --clusters only where the strategy splits its draws (elsewhere it has no effect).
        let clusters: &[&str] =
            if matches!(strategy, "instanced" | "prerecorded") { &[] } else { &["--clusters", "16"] };
        let args: Vec<&str> =
            args.into_iter().chain(["--submission", strategy]).chain(clusters.iter().copied()).collect();
        render(&args, &dir.join(format!("{strategy}.png")));
    }
}
