//! What lavapipe has and other devices may lack, hidden by the capability mask (`MEADOW_HIDE`,
//! `vk::capabilities`), through the binary: each fallback renders, each refusal is one clear
//! line with its exit code, validation-clean.

mod support;

use std::process::Output;

use meadow::imagediff::box_filtered_difference;
use support::{meadow, scratch, transcript, Picture};

const SCENE: [&str; 6] = ["--blades", "3000", "--size", "160x96", "--mode", "texture"];

/// `meadow render --validation SCENE extra --out out` with `MEADOW_HIDE=hide`.
fn render_hiding(hide: &str, extra: &[&str], out: &std::path::Path) -> Output {
    meadow()
        .env("MEADOW_HIDE", hide)
        .args(["render", "--validation", "--device", support::DEVICE])
        .args(SCENE)
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .expect("run meadow")
}

#[test]
fn keyframes_fall_back_to_a_format_the_device_can_sample() {
    let dir = scratch("portability-format");
    let (hidden, normal) = (dir.join("hidden.png"), dir.join("normal.png"));
    let output = render_hiding("format:R16G16B16A16_UNORM", &[], &hidden);
    support::assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("cannot sample R16G16B16A16_UNORM: keyframes encoded Rgba8x2 instead"),
        "{}",
        transcript(&output)
    );
    let output = render_hiding("", &[], &normal);
    support::assert_clean(&output);
    assert!(!String::from_utf8_lossy(&output.stdout).contains("note:"), "{}", transcript(&output));
    // The 8-bit pair encodes the same poses to within its rounding: the same picture, nearly.
    let (a, b) = (Picture::load(&hidden), Picture::load(&normal));
    let diff = box_filtered_difference(&a.rgb, &b.rgb, a.width, a.height, 8);
    assert!(diff.mean_percent < 0.5, "{diff:?}");
}

#[test]
fn missing_features_limits_and_formats_are_refused_in_one_line() {
    let dir = scratch("portability-refusals");
    let cases: [(&str, &[&str], i32, &str); 4] = [
        ("separateDepthStencilLayouts", &[], 1, "lacks separateDepthStencilLayouts"),
        ("maxPerStageDescriptorStorageBuffers=4", &[], 1, "allows 4 storage buffers per shader stage"),
        ("format:R16G16B16A16_SFLOAT", &["--msaa", "4"], 2, "supported: 1"),
        ("timestampz", &[], 1, "MEADOW_HIDE: unknown entry 'timestampz'"),
    ];
    for (hide, extra, code, message) in cases {
        let out = dir.join("refused.png");
        let output = render_hiding(hide, extra, &out);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(code), "{hide}: {}", transcript(&output));
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
        assert_eq!(errors.len(), 1, "{hide}: {stderr}");
        assert!(errors[0].contains(message), "{hide}: {stderr}");
        assert!(transcript(&output).contains("validation: 0 messages"), "{hide}: {}", transcript(&output));
        assert!(!out.exists(), "{hide}: a refused render wrote {}", out.display());
    }
    // Without the mask, multisampling is there: the refusal above came from the mask.
    let output = render_hiding("", &["--msaa", "4"], &dir.join("msaa.png"));
    support::assert_clean(&output);
}

#[test]
fn without_timestamps_render_says_unavailable_and_the_measuring_commands_refuse() {
    let dir = scratch("portability-timestamps");
    let out = dir.join("untimed.png");
    let output = render_hiding("timestamps", &["--frames", "2"], &out);
    support::assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("gpu: unavailable (") && !stdout.contains("gpu median"), "{}", transcript(&output));
    assert!(out.exists());
    // With timestamps, the same render measures its passes.
    let output = render_hiding("", &["--frames", "2"], &dir.join("timed.png"));
    assert!(String::from_utf8_lossy(&output.stdout).contains("gpu median over 2 frames"), "{}", transcript(&output));
    let measuring: [&[&str]; 4] = [
        &["bench", "--preset", "quick"],
        &["overhead", "--blades", "1000"],
        &["timing", "--blades", "1000", "--frames", "2"],
        &["render", "--blades", "1000", "--budget-ms", "10"],
    ];
    for args in measuring {
        let target = dir.join("refused");
        let output = meadow()
            .env("MEADOW_HIDE", "timestamps")
            .args(args)
            .args(["--device", support::DEVICE, "--out"])
            .arg(&target)
            .output()
            .expect("run meadow");
        assert_eq!(output.status.code(), Some(1), "{args:?}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.starts_with("error: ") && stderr.contains("timestamps"), "{args:?}: {stderr}");
        assert!(!target.exists(), "{args:?} left {}", target.display());
    }
}

#[test]
fn debug_utils_is_optional_without_validation() {
    let dir = scratch("portability-debug-utils");
    let render_plain = |hide: &str, name: &str| {
        let out = dir.join(name);
        let output = meadow()
            .env("MEADOW_HIDE", hide)
            .args(["render", "--device", support::DEVICE])
            .args(SCENE)
            .arg("--out")
            .arg(&out)
            .output()
            .expect("run meadow");
        assert_eq!(output.status.code(), Some(0), "{hide}: {}", transcript(&output));
        std::fs::read(&out).expect("png")
    };
    // No names, no labels, no messenger: the same picture.
    assert!(render_plain("debug_utils", "without.png") == render_plain("", "with.png"));
    // Validation counts its messages through the extension: refused, in one line.
    let output = render_hiding("debug_utils", &[], &dir.join("validated.png"));
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().filter(|l| l.starts_with("error: ")).count(), 1, "{stderr}");
    assert!(stderr.contains("VK_EXT_debug_utils"), "{stderr}");
}

#[test]
fn depth_falls_back_to_the_24_and_16_bit_formats() {
    let dir = scratch("portability-depth");
    let reference = dir.join("d32.png");
    support::assert_clean(&render_hiding("", &[], &reference));
    let reference = Picture::load(&reference);
    for (hide, format) in
        [("format:D32_SFLOAT", "X8_D24_UNORM_PACK32"), ("format:D32_SFLOAT,format:X8_D24_UNORM_PACK32", "D16_UNORM")]
    {
        for extra in [&[][..], &["--msaa", "4", "--brute-force"][..]] {
            let out = dir.join("fallback.png");
            let output = render_hiding(hide, extra, &out);
            support::assert_clean(&output);
            let stdout = String::from_utf8_lossy(&output.stdout);
            assert!(stdout.contains(&format!("depth in {format} instead")), "{hide}: {}", transcript(&output));
            if extra.is_empty() {
                // Reversed Z keeps even 16 bits close over the field: nearly the same picture.
                let picture = Picture::load(&out);
                let diff = box_filtered_difference(&picture.rgb, &reference.rgb, picture.width, picture.height, 8);
                assert!(diff.mean_percent < 0.5, "{hide}: {diff:?}");
            }
        }
    }
}

#[test]
fn the_floor_with_per_blade_evaluation_runs_no_pose_pass() {
    // `--mode floor` draws pre-expanded static blades: there is nothing to evaluate, so the
    // frame's passes are the terrain and the floor's blades, and `--eval blade` is refused
    // (`cli::effect`) rather than ignored. The control: the same evaluation with keyframes runs
    // the pose pass.
    let dir = scratch("portability-floor-eval");
    let run = |mode: &str, extra: &[&str]| {
        meadow()
            .args(["render", "--validation", "--device", support::DEVICE, "--blades", "2000", "--size", "64x64"])
            .args(["--mode", mode])
            .args(extra)
            .arg("--out")
            .arg(dir.join(format!("{mode}.png")))
            .output()
            .expect("run meadow")
    };
    let passes = |mode: &str, extra: &[&str]| {
        let output = run(mode, extra);
        support::assert_clean(&output);
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        let line = stdout.lines().find(|l| l.starts_with("gpu: ")).map(str::to_owned);
        line.unwrap_or_else(|| panic!("{}", transcript(&output)))
    };
    let floor = passes("floor", &[]);
    assert!(floor.contains("(terrain ") && floor.contains(", blades ") && !floor.contains("blade poses"), "{floor}");
    let refused = run("floor", &["--eval", "blade"]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{}", transcript(&refused));
    assert!(stderr.starts_with("error: --eval has no effect with --mode floor"), "{stderr}");
    let texture = passes("texture", &["--eval", "blade", "--brute-force"]);
    assert!(texture.contains("blade poses"), "{texture}");
}

#[test]
fn the_storage_buffer_limit_refuses_exactly_below_what_meadow_binds() {
    // From the spec minimum (4) up: each refusal names a stage and how many storage buffers it
    // binds; at that many, the next stage's need shows, until the render runs. So the test
    // follows meadow's real need as bindings are added, instead of a number written here.
    let dir = scratch("portability-storage-limit");
    let out = dir.join("x.png");
    let mut limit = 4u32;
    let mut needs = Vec::new();
    loop {
        let output = render_hiding(&format!("maxPerStageDescriptorStorageBuffers={limit}"), &[], &out);
        if output.status.code() == Some(0) {
            break;
        }
        assert_eq!(output.status.code(), Some(1), "limit {limit}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        let said = format!("allows {limit} storage buffers per shader stage; meadow's ");
        assert!(stderr.contains(&said), "limit {limit}: {stderr}");
        let binds: u32 = stderr
            .split(" stage binds ")
            .nth(1)
            .and_then(|rest| rest.split(|c: char| !c.is_ascii_digit()).next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("limit {limit}: {stderr}"));
        assert!(binds > limit, "limit {limit}: refused although its stage binds {binds}");
        needs.push(binds);
        limit = binds;
        assert!(needs.len() < 8, "{needs:?}");
    }
    assert!(!needs.is_empty(), "the spec minimum of 4 is enough: no refusal to test");
    // The last need found is what the device must allow: that many renders (the loop's end), one
    // fewer is refused.
    support::assert_clean(&render_hiding(&format!("maxPerStageDescriptorStorageBuffers={limit}"), &[], &out));
    let below = render_hiding(&format!("maxPerStageDescriptorStorageBuffers={}", limit - 1), &[], &out);
    assert_eq!(below.status.code(), Some(1), "{needs:?}: {}", transcript(&below));
}

#[test]
fn portability_enumeration_is_requested_when_the_loader_offers_it() {
    // The loader here offers VK_KHR_portability_enumeration: meadow enables it (so MoltenVK
    // devices would be listed) and says so; hidden, the instance is made without it and the
    // devices are still listed. No device here is a portability subset (none says so).
    for (hide, said) in [
        ("", "loader: VK_KHR_portability_enumeration enabled"),
        ("portability_enumeration", "loader: no VK_KHR_portability_enumeration"),
    ] {
        let output = meadow().env("MEADOW_HIDE", hide).args(["devices", "--validation"]).output().expect("run meadow");
        support::assert_clean(&output);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(stdout.lines().next().is_some_and(|l| l.starts_with(said)), "{hide}: {stdout}");
        assert!(stdout.lines().any(|l| l.starts_with("0: llvmpipe")), "{hide}: {stdout}");
        assert!(!stdout.contains("portability subset"), "{hide}: {stdout}");
    }
}
