//! Bad input through the real binary: exit code 2, one `error:` line naming the problem, no panic,
//! no file written.

mod support;

use support::{meadow, scratch, transcript};

/// Run `meadow render ARGS --out OUT` and check the refusal.
fn refused(case: &str, args: &[&str], expect_in_message: &str) {
    let dir = scratch(&format!("bad-{case}"));
    let out = dir.join("out.png");
    let mut cmd = meadow();
    cmd.arg("render").args(args);
    if !args.contains(&"--device") {
        cmd.args(["--device", support::DEVICE]);
    }
    if !args.contains(&"--out") {
        cmd.arg("--out").arg(&out);
    }
    let output = cmd.output().expect("run meadow");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{case}: {}", transcript(&output));
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{case}: one line expected: {}", transcript(&output));
    assert!(lines[0].starts_with("error: "), "{case}: {}", lines[0]);
    assert!(lines[0].contains(expect_in_message), "{case}: '{}' does not mention '{expect_in_message}'", lines[0]);
    assert!(!stderr.contains("panicked"), "{case}: panic");
    assert!(!out.exists(), "{case}: a file was written");
    assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).unwrap_or(0), 0, "{case}: stray files");
}

#[test]
fn zero_and_malformed_counts() {
    refused("blades-0", &["--blades", "0"], "at least 1 blade");
    refused("blades-text", &["--blades", "many"], "many");
    refused("blades-huge", &["--blades", "99999999999"], "99999999999");
    refused("segments-0", &["--segments", "0"], "outside 1..=16");
    refused("segments-17", &["--segments", "17"], "outside 1..=16");
    refused("per-instance-0", &["--blades-per-instance", "0"], "outside 1..=1024");
    refused("frames-0", &["--frames", "0"], "--frames");
}

#[test]
fn culling_and_lod_inputs() {
    refused("lod-segments-empty", &["--lod-segments", ""], "at least one");
    refused("lod-segments-0", &["--lod-segments", "4,0"], "outside 1..=16");
    refused("lod-segments-17", &["--lod-segments", "17"], "outside 1..=16");
    refused("lod-segments-increasing", &["--lod-segments", "1,2,4"], "decrease");
    refused("lod-segments-over-segments", &["--segments", "2", "--lod-segments", "4,2,1"], "over --segments 2");
    refused("view-distance-0", &["--view-distance", "0"], "above 0");
    refused("view-distance-nan", &["--view-distance", "NaN"], "NaN");
    refused("view-distance-over-10-km", &["--view-distance", "10001"], "over the 10000 m");
    refused(
        "blade-distance-over-view",
        &["--field", "infinite", "--view-distance", "100", "--blade-distance", "120"],
        "--blade-distance 120 is over --view-distance 100",
    );
    refused("blade-distance-0", &["--blade-distance", "0"], "above 0");
    refused("blade-distance-nan", &["--blade-distance", "NaN"], "NaN");
    refused("lod-scale-negative", &["--lod-scale", "-1"], "above 0");
    refused("submission-with-cull", &["--submission", "mdi"], "--brute-force");
    refused("budget-0", &["--budget-ms", "0"], "above 0");
    refused("budget-negative", &["--budget-ms", "-5"], "above 0");
    refused("budget-nan", &["--budget-ms", "NaN"], "NaN");
    refused("budget-brute-force", &["--budget-ms", "30", "--brute-force"], "--brute-force");
}

#[test]
fn sizes() {
    refused("size-0x0", &["--size", "0x0"], "empty");
    refused("size-malformed", &["--size", "1280"], "WIDTHxHEIGHT");
    refused("size-huge", &["--size", "100000x100000"], "maxImageDimension2D");
}

#[test]
fn non_finite_camera() {
    refused("camera-nan", &["--camera", "0,NaN,0,0,0"], "NaN");
    refused("camera-inf", &["--camera", "0,1.7,inf,0,0"], "inf");
    refused("camera-neg-inf", &["--camera", "-inf,1.7,0,0,0"], "-inf");
    refused("camera-short", &["--camera", "0,1,2"], "five numbers");
    refused("camera-pitch", &["--camera", "0,1,2,0,90"], "pitch");
    refused("camera-preset", &["--camera", "panorama"], "unknown camera preset 'panorama'");
}

#[test]
fn fog_and_relief() {
    refused("fog-negative", &["--fog", "-0.01"], "negative");
    refused("fog-nan", &["--fog", "NaN"], "NaN");
    refused("relief-unknown", &["--field", "infinite", "--relief", "alps"], "alps");
    refused("relief-without-field", &["--blades", "1000", "--relief", "hills"], "--field");
}

#[test]
fn device_limits_and_budget() {
    // lavapipe: maxStorageBufferRange = 128 MiB, i.e. 4 194 304 blades of 32 bytes.
    refused("blades-over-storage-range", &["--blades", "5000000"], "maxStorageBufferRange");
    // Brute force evaluates every blade: 1M x 16 segments of records is 194 MiB, over the range
    // (the cull needs records for the drawn blades only).
    let eval = ["--brute-force", "--eval", "blade", "--blades", "1000000", "--segments", "16"];
    refused("eval-blade-brute-over-range", &eval, "194 MiB of evaluated levels");
    // 16384² RGBA colour + depth + readback = 3 GiB: over the 2 GiB heap and budget.
    refused("target-over-budget", &["--size", "16384x16384"], "16384x16384");
}

#[test]
fn animation_inputs() {
    refused("poses-0", &["--poses", "0"], "outside 8..=1000000");
    refused("wind-nan", &["--wind", "30,NaN"], "NaN");
    refused("source-negative-sigma", &["--source", "0,0,1,-2"], "negative");
    refused("calm-inverted", &["--calm", "2,0,1,1"], "inverted");
    // The analytic wind field's parameter block holds 64 calm areas.
    let calm: Vec<&str> = (0..65).flat_map(|_| ["--calm", "0,0,1,1"]).collect();
    refused("calm-over-64", &calm, "65 calm areas: at most 64");
    refused("collider-radius-0", &["--collider", "sphere:0,0.2,0,0"], "radius");
    // Issue 34: a radius 0, negative or NaN; a velocity that is NaN.
    refused("collider-radius-negative", &["--collider", "ellipsoid:0,0.2,0,0.3,-0.2,0.3"], "radius");
    refused("collider-radius-nan", &["--collider", "sphere:0,0.2,0,NaN"], "not a finite number");
    refused("collider-velocity-nan", &["--collider", "sphere:0,0.2,0,0.3,1,NaN,0"], "not a finite number");
    refused("collider-velocity-short", &["--collider", "sphere:0,0.2,0,0.3,1,0"], "VX,VY,VZ");
    // Sources and colliders have room of their own in the emitter buffers: 64 and 128.
    let colliders: Vec<&str> = (0..129).flat_map(|_| ["--collider", "sphere:0,0.2,0,0.3"]).collect();
    refused("colliders-over-128", &colliders, "129 colliders: at most 128");
    let sources: Vec<&str> = (0..65).flat_map(|_| ["--source", "0,0,1,2"]).collect();
    refused("sources-over-64", &sources, "65 wind sources: at most 64");
    refused("cluster-size-0", &["--cluster-size", "0"], "cluster size");
    refused("time-inf", &["--time", "inf"], "inf");
    // The fixed time step (issue 29 item 4): above 0, finite, at most 1/15 s.
    refused("dt-0", &["--dt", "0"], "must be above 0");
    refused("dt-negative", &["--dt", "-0.01"], "must be above 0");
    refused("dt-nan", &["--dt", "NaN"], "not a finite number");
    // The pressed map (issue 34): recovery and regrowth above 0 and finite; 256 colliders and
    // cuts together; each only where it has an effect.
    refused("recovery-0", &["--collider", "sphere:0,0.2,0,0.3", "--recovery-s", "0"], "must be above 0");
    refused("recovery-negative", &["--collider", "sphere:0,0.2,0,0.3", "--recovery-s", "-2"], "must be above 0");
    refused("recovery-nan", &["--collider", "sphere:0,0.2,0,0.3", "--recovery-s", "NaN"], "not a finite number");
    refused("regrow-0", &["--cut", "sphere:0,0.2,0,0.3", "--regrow-s", "0"], "must be above 0");
    refused("regrow-negative", &["--cut", "sphere:0,0.2,0,0.3", "--regrow-s", "-1"], "must be above 0");
    refused("regrow-nan", &["--cut", "sphere:0,0.2,0,0.3", "--regrow-s", "NaN"], "not a finite number");
    refused("cut-radius-nan", &["--cut", "sphere:0,0.2,0,NaN"], "not a finite number");
    let cuts: Vec<&str> = (0..129).flat_map(|_| ["--cut", "sphere:0,0.2,0,0.3"]).collect();
    let both: Vec<&str> = [&colliders[..256], &cuts[..]].concat();
    refused("cuts-over-256", &both, "257 colliders and cuts: at most 256 together");
    refused("recovery-without-collider", &["--recovery-s", "5"], "no --collider");
    refused("regrow-without-cut", &["--regrow-s", "5"], "no --cut");
    refused("cut-per-vertex", &["--cut", "sphere:0,0.2,0,0.3", "--eval", "vertex"], "posed per vertex or neutral");
    refused("dt-over-1-15", &["--dt", "0.1"], "over 1/15 s");
    refused("dt-fraction-over", &["--dt", "1/10"], "over 1/15 s");
    refused("poses-over-texture", &["--poses", "1000000"], "maxImageDimension2D");
    // 10 000 stored poses × 16 levels × 8 bytes = 1.28 MB of uniform data: over 64 KiB.
    refused(
        "uniform-overflow",
        &["--mode", "uniform", "--poses", "40000", "--segments", "16"],
        "maxUniformBufferRange of 65536 (use --mode texture",
    );
}

#[test]
fn files_and_devices() {
    refused("out-dir-missing", &["--out", "/nonexistent/dir/x.png"], "does not exist");
    refused("device-unknown", &["--device", "no-such-gpu"], "no-such-gpu");
    refused("device-index", &["--device", "42"], "no such device");
}

#[test]
fn missing_validation_layer_fails_instead_of_skipping() {
    let dir = scratch("no-layer");
    let out = dir.join("out.png");
    let output = meadow()
        .env("VK_LAYER_PATH", dir.join("no-layers-here"))
        .args(["render", "--validation", "--blades", "10", "--size", "16x16", "--out"])
        .arg(&out)
        .output()
        .expect("run meadow");
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    assert!(String::from_utf8_lossy(&output.stderr).contains("VK_LAYER_KHRONOS_validation is not installed"));
    assert!(!out.exists());
}

/// Issue 11's list: what a hostile campaign found on the command line itself.
#[test]
fn command_line_corner_cases() {
    // No subcommand: one `error:` line naming them, exit 2.
    let output = meadow().output().expect("run meadow");
    assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: a subcommand is needed: render, view"), "{stderr}");
    // A negative time is a value, refused as such (not read as a flag).
    refused("time-negative", &["--time", "-1"], "negative");
    // `--clusters` means nothing to the instanced draw: its default does not refuse a small field.
    let dir = scratch("bad-small-field");
    let out = dir.join("small.png");
    let args = ["render", "--blades", "10", "--size", "32x32", "--device", support::DEVICE, "--out"];
    let output = meadow().args(args).arg(&out).output().expect("run meadow");
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
    assert!(out.exists());
    // ... but more clusters than blades for a per-cluster strategy are refused by `timing` too,
    // before its output directory exists.
    let timing_out = dir.join("timing");
    let output = meadow()
        .args(["timing", "--blades", "100", "--clusters", "500", "--submission", "per-cluster", "--brute-force"])
        .args(["--device", support::DEVICE, "--out"])
        .arg(&timing_out)
        .output()
        .expect("run meadow");
    assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
    assert!(String::from_utf8_lossy(&output.stderr).contains("--clusters 500 exceeds --blades 100"));
    assert!(!timing_out.exists(), "timing created its directory before refusing");
    // Without --clusters, a per-cluster strategy on a small field: the message says where the 64
    // comes from instead of blaming a flag that was not given.
    refused(
        "clusters-default",
        &["--blades", "63", "--brute-force", "--submission", "per-cluster"],
        "(--submission per-cluster splits the blades into --clusters clusters, 64 unless given)",
    );
}

/// No Vulkan driver, with validation: a runtime failure (exit 1) with one `error:` line first, and
/// the loader's messages after it, counted in the `validation: N messages` line like any other.
#[test]
fn a_missing_driver_is_a_runtime_error_with_its_messages_counted() {
    let dir = scratch("no-driver");
    let output = meadow()
        .env("VK_ICD_FILENAMES", dir.join("no-such-icd.json"))
        .env("VK_DRIVER_FILES", dir.join("no-such-icd.json"))
        .args(["render", "--validation", "--blades", "100", "--out"])
        .arg(dir.join("x.png"))
        .output()
        .expect("run meadow");
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    // The error first, saying what is missing; then what the loader said while failing, each
    // line a counted validation message.
    let lines: Vec<&str> = stderr.lines().collect();
    assert!(lines[0].starts_with("error: no Vulkan driver found ("), "{stderr}");
    assert!(lines.len() > 1 && lines[1..].iter().all(|l| l.starts_with("validation [")), "{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let counted = stdout.lines().find_map(|l| l.strip_prefix("validation: ")).expect("a validation line");
    assert_eq!(counted, format!("{} messages", lines.len() - 1), "the loader's complaints are counted");
    assert!(!dir.join("x.png").exists());
}

/// Issue 11: a script line of megabytes (an unknown action, key or value) is refused in one
/// bounded line, before any display is needed.
#[test]
fn a_huge_script_line_is_refused_in_a_bounded_line() {
    let dir = scratch("bad-huge-script");
    let words = [
        "q".repeat(10_000_000),
        format!("press {}", "a".repeat(10_000_000)),
        format!("camera {}", "1".repeat(10_000_000)),
    ];
    for (i, words) in words.iter().enumerate() {
        let script = dir.join(format!("long-{i}.txt"));
        std::fs::write(&script, format!("2 {words}\n")).expect("write script");
        let output = meadow()
            .arg("view")
            .arg("--script")
            .arg(&script)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("run meadow");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            output.status.code(),
            Some(2),
            "case {i}: exit {:?}, {} bytes of stderr",
            output.status.code(),
            stderr.len()
        );
        assert_eq!(stderr.lines().count(), 1, "case {i}: {} lines", stderr.lines().count());
        assert!(stderr.starts_with("error: --script ") && stderr.contains("line 1: "), "case {i}: {:.300}", stderr);
        assert!(stderr.len() < 600, "case {i}: {} bytes of error", stderr.len());
    }
}

#[test]
fn responses_refuse_what_only_keyframes_have() {
    refused("animation-unknown", &["--animation", "verlett"], "verlett");
    refused("wind-field-unknown", &["--wind-field", "fluidd"], "fluidd");
    refused("fluid-grid-zero", &["--wind-field", "fluid", "--fluid-grid", "0,16,32"], "0 cells");
    refused("fluid-grid-limit", &["--wind-field", "fluid", "--fluid-grid", "60000,4,4"], "3-D image limit");
    // At lavapipe's limit of 4 096 the grid fits, and the inflow's ring of ghost columns (two more) does not.
    refused("fluid-grid-ring", &["--wind-field", "fluid", "--fluid-grid", "4096,4,4"], "inflow ring is 4098 texels");
    refused(
        "fluid-grid-budget",
        &["--wind-field", "fluid", "--fluid-grid", "2048,64,2048"],
        "the fluid wind's grid needs",
    );
    refused("fluid-cell-zero", &["--wind-field", "fluid", "--fluid-cell", "0,1"], "0 m is not a length");
    refused("fluid-cell-negative", &["--wind-field", "fluid", "--fluid-cell", "-1,1"], "-1 m is not a length");
    refused("fluid-cell-nan", &["--wind-field", "fluid", "--fluid-cell", "nan,1"], "not a finite number");
    refused("source-height-negative", &["--wind-field", "fluid", "--source", "0,0,1,2,-1"], "source height -1");
    refused(
        "source-height-analytic",
        &["--source", "0,0,1,2,0.8"],
        "--source …,HEIGHT has no effect with a --wind-field other than fluid",
    );
    refused("source-height-perlin", &["--wind-field", "perlin", "--source", "0,0,1,2,1,0,0.8"], "--source …,HEIGHT");
    refused("source-height-nan", &["--wind-field", "fluid", "--source", "0,0,1,2,nan"], "not a finite number");
    refused(
        "fluid-brute-force",
        &["--wind-field", "fluid", "--brute-force"],
        "--wind-field fluid has no effect with --brute-force",
    );
    refused(
        "fluid-attenuation",
        &["--wind-field", "fluid", "--source", "0,0,1,1", "--attenuation", "blade"],
        "--attenuation has no effect with --wind-field fluid",
    );
    refused("fluid-grid-analytic", &["--fluid-grid", "16,8,16"], "--fluid-grid has no effect");
    refused(
        "wind-field-gusts",
        &["--wind-field", "perlin", "--no-gusts"],
        "--no-gusts has no effect with --wind-field perlin",
    );
    refused(
        "animation-poses",
        &["--animation", "sine-object", "--poses", "16"],
        "--poses has no effect with an --animation other than keyframes",
    );
    refused("animation-mode", &["--animation", "sine-vertex", "--mode", "uniform"], "--mode has no effect");
    refused("animation-eval", &["--animation", "static", "--eval", "blade"], "--eval has no effect");
    refused(
        "animation-floor",
        &["--mode", "floor", "--animation", "keyframes"],
        "--animation has no effect with --mode floor",
    );
    refused("animation-static-wind", &["--animation", "static", "--wind", "0,1"], "--wind has no effect");
    refused("animation-time", &["--animation", "sine-object", "--time", "-1"], "--time");
    refused("stiffness-range", &["--animation", "verlet", "--stiffness", "500"], "outside 1..=400");
    refused("stiffness-nan", &["--animation", "verlet", "--stiffness", "NaN"], "not a finite number");
    refused("damping-range", &["--animation", "verlet", "--damping", "-1"], "outside 0..=20");
    refused(
        "stiffness-keyframes",
        &["--stiffness", "50"],
        "--stiffness has no effect with an --animation other than verlet, inertial or virtual-inertial",
    );
    refused("verlet-poses", &["--animation", "verlet", "--poses", "16"], "--poses has no effect");
    refused("inertial-stiffness-range", &["--animation", "inertial", "--stiffness", "0"], "outside 1..=400");
    refused("inertial-poses", &["--animation", "inertial", "--poses", "16"], "--poses has no effect");
    refused("virtual-damping-range", &["--animation", "virtual-inertial", "--damping", "21"], "outside 0..=20");
    refused("virtual-poses", &["--animation", "virtual-inertial", "--poses", "16"], "--poses has no effect");
}

/// `timing --fly`: a speed above 0 and at most 1 000 m/s, refused in one line before the output
/// directory exists.
#[test]
fn a_flight_speed_must_be_above_0_and_finite() {
    for (case, speed, why) in [
        ("fly-zero", "0", "above 0"),
        ("fly-nan", "NaN", "finite"),
        ("fly-negative", "-3", "above 0"),
        ("fly-fast", "2000", "over"),
    ] {
        let dir = scratch(&format!("bad-{case}"));
        let out = dir.join("timing");
        let output = meadow()
            .args(["timing", "--blades", "100", "--brute-force", "--fly", speed, "--device", support::DEVICE, "--out"])
            .arg(&out)
            .output()
            .expect("run meadow");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{case}: {}", transcript(&output));
        assert_eq!(stderr.lines().count(), 1, "{case}: {}", transcript(&output));
        assert!(stderr.starts_with("error: ") && stderr.contains(why), "{case}: {stderr}");
        assert!(!out.exists(), "{case}: timing created its directory before refusing");
    }
}
