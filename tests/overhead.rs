//! Draw-submission strategies (`meadow overhead`, `meadow render --submission`): every strategy
//! draws the same picture under validation; the overhead harness reports every strategy with
//! consistent numbers; bad arguments exit 2.

mod support;

use serde_json::Value;
use support::{assert_clean, meadow, scratch, transcript, Picture};

const STRATEGIES: [&str; 7] = ["instanced", "per-cluster", "indirect", "mdi", "mdi-count", "secondary", "prerecorded"];

#[test]
fn every_strategy_draws_the_same_picture() {
    let dir = scratch("submission-pictures");
    let render = |strategy: &str| {
        let out = dir.join(format!("{strategy}.png"));
        // 37 clusters over 5000 blades: uneven ranges; two frames so `prerecorded` reuses its
        // command buffer for the picture that is written.
        let args = ["--blades", "5000", "--size", "160x90", "--frames", "2", "--submission", strategy, "--brute-force"];
        // --clusters only where the strategy splits its draws (elsewhere it has no effect).
        let clusters: &[&str] =
            if matches!(strategy, "instanced" | "prerecorded") { &[] } else { &["--clusters", "37"] };
        let args: Vec<&str> = args.iter().chain(clusters).copied().collect();
        let output = support::render(&args, &out);
        assert_clean(&output);
        Picture::load(&out)
    };
    let reference = render("instanced");
    let sky = reference.pixel(80, 2);
    let grass = (0..90).filter(|y| reference.pixel(80, *y) != sky).count();
    assert!(grass > 20, "the reference shows grass");
    for strategy in &STRATEGIES[1..] {
        let picture = render(strategy);
        assert!(picture.rgb == reference.rgb, "{strategy} differs from instanced");
    }
}

#[test]
fn overhead_reports_every_strategy() {
    let dir = scratch("overhead-tiny");
    let output = meadow()
        .args(["overhead", "--validation", "--device", support::DEVICE, "--blades", "2000", "--segments", "1"])
        .args(["--clusters", "1,50", "--frames", "2", "--warmup", "1", "--size", "64x48", "--out"])
        .arg(&dir)
        .output()
        .expect("run meadow overhead");
    assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("ns/draw") && stdout.contains("mdi-count"), "{stdout}");

    let doc: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("overhead.json")).expect("overhead.json"))
        .expect("JSON");
    assert_eq!(doc["kind"], "overhead");
    let rows = doc["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 2 * STRATEGIES.len(), "{stdout}");
    for row in rows {
        let strategy = row["strategy"].as_str().expect("strategy");
        let clusters = row["clusters"].as_u64().expect("clusters");
        assert!(row["unsupported"].is_null(), "lavapipe supports {strategy}: {row}");
        let executed = row["draws_executed"].as_u64().expect("draws executed");
        let recorded = row["draw_calls_recorded"].as_u64().expect("calls");
        let (expect_executed, expect_recorded) = match strategy {
            "instanced" | "prerecorded" => (1, 1),
            "mdi" | "mdi-count" => (clusters, 1),
            _ => (clusters, clusters),
        };
        assert_eq!((executed, recorded), (expect_executed, expect_recorded), "{strategy} x {clusters}");
        // The passes' GPU time, and the read-back copy after them apart.
        assert!(row["gpu_ms"].as_f64().expect("gpu ms") > 0.0 && row["readback_ms"].as_f64() > Some(0.0), "{row}");
        for f in row["frames"].as_array().expect("frames") {
            assert!(f["gpu_ms"].as_f64() > Some(0.0) && f["readback_ms"].as_f64() > Some(0.0), "{f}");
        }
        assert!(row["cpu_submit_us"].as_f64().expect("submit") > 0.0);
        let record = row["cpu_record_us"].as_f64().expect("record");
        assert!(record >= 0.0);
        let ns = row["ns_per_draw"].as_f64().expect("ns per draw");
        assert!((ns - record * 1e3 / executed as f64).abs() <= 1e-6 * ns.max(1.0), "{row}");
        assert_eq!(row["frames"].as_array().expect("frames").len(), 2);
    }
    let csv = std::fs::read_to_string(dir.join("overhead.csv")).expect("overhead.csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("clusters,strategy,frame,cpu_record_us,cpu_submit_us,gpu_ms"));
    let body: Vec<&str> = lines.collect();
    assert_eq!(body.len(), 2 * STRATEGIES.len() * 2);
    for line in body {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), 6, "{line}");
        assert!(fields[5].parse::<f64>().expect("gpu_ms") > 0.0, "{line}");
    }
}

/// `meadow overhead` of 200 blades at 1 and 8 clusters with `MEADOW_HIDE=hide`, asserted clean:
/// `(strategy, clusters) -> unsupported reason` of every row (`None`: measured, GPU time > 0).
fn overhead_hiding(hide: &str) -> Vec<(String, u64, Option<String>)> {
    let dir = scratch(&format!("overhead-hide-{hide}"));
    let output = meadow()
        .env("MEADOW_HIDE", hide)
        .args(["overhead", "--validation", "--device", support::DEVICE, "--blades", "200", "--segments", "1"])
        .args(["--clusters", "1,8", "--frames", "1", "--warmup", "0", "--size", "32x24", "--out"])
        .arg(&dir)
        .output()
        .expect("run meadow overhead");
    assert_clean(&output);
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("overhead.json")).expect("overhead.json"))
        .expect("JSON");
    let rows = doc["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 2 * STRATEGIES.len(), "{hide}: {}", transcript(&output));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut out = Vec::new();
    for row in rows {
        let (strategy, clusters) = (row["strategy"].as_str().expect("strategy"), row["clusters"].as_u64().expect("n"));
        let why = row["unsupported"].as_str().map(str::to_string);
        match &why {
            Some(why) => assert!(stdout.contains(&format!("{strategy:<12} unsupported: {why}")), "{stdout}"),
            None => assert!(row["gpu_ms"].as_f64() > Some(0.0), "{hide}: {strategy} x {clusters} measured: {row}"),
        }
        out.push((strategy.to_string(), clusters, why));
    }
    out
}

#[test]
fn draw_features_the_device_lacks_make_only_what_needs_them_unsupported() {
    // Without drawIndirectCount: mdi-count, at any count; every other strategy runs.
    for (strategy, clusters, why) in overhead_hiding("drawIndirectCount") {
        let expect = (strategy == "mdi-count").then(|| "no drawIndirectCount".to_string());
        assert_eq!(why, expect, "{strategy} x {clusters}");
    }
    // Without multiDrawIndirect the spec makes maxDrawIndirectCount 1: one draw of either
    // multi-draw is valid; of 8, mdi lacks the feature and mdi-count exceeds the limit.
    for (strategy, clusters, why) in overhead_hiding("multiDrawIndirect") {
        let expect = match (strategy.as_str(), clusters) {
            ("mdi", 8) => Some("no multiDrawIndirect".to_string()),
            ("mdi-count", 8) => Some("8 draws exceed maxDrawIndirectCount 1".to_string()),
            _ => None,
        };
        assert_eq!(why, expect, "{strategy} x {clusters}");
    }
}

#[test]
fn bad_overhead_arguments_exit_2() {
    for args in [
        &["overhead", "--clusters", "0"][..],
        &["overhead", "--strategies", "mesh"][..],
        &["overhead", "--blades", "10", "--clusters", "11"][..],
        &["overhead", "--frames", "0"][..],
        &["render", "--submission", "mdi", "--blades", "10", "--clusters", "11"][..],
    ] {
        let output = meadow().args(args).output().expect("run");
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{args:?}: {stderr}");
    }
}
