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

/// The far-field band of a `width`×`height` picture from the default camera: rows from the
/// hill's outline down to 40 % of the height, where the blades are a pixel wide or less.
fn far_band(rgb: &[u8], width: u32, height: u32) -> (Vec<u8>, u32) {
    let (top, bottom) = (height * 3 / 10, height * 6 / 10);
    let row = 3 * width as usize;
    (rgb[top as usize * row..bottom as usize * row].to_vec(), bottom - top)
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
    // Reference: twice the resolution, 4 samples, the alpha test (not the method under test),
    // downsampled in linear light: 16 samples per pixel.
    let big = shot("reference.png", &["--size", "640x360", "--no-alpha-to-coverage"]);
    let reference = downsample_2x_srgb(&big.rgb, 640, 360);
    let (reference, rows) = far_band(&reference, w, h);
    let error = |p: &Picture| {
        let (band, _) = far_band(&p.rgb, w, h);
        box_filtered_difference(&band, &reference, w, rows, 8).mean_percent
    };
    let (with, without) = (error(&coverage), error(&alpha_test));
    eprintln!("far field against the reference: alpha to coverage {with:.3} %, alpha test {without:.3} %");
    assert!(with < without, "alpha to coverage {with:.3} % is not closer than the alpha test {without:.3} %");
}
