//! Outputs are whole or absent (the first part of the hardening issue): a write that fails
//! half-way leaves neither the file nor a temporary, and a target that is not a regular file is
//! refused before any work.

mod support;

use std::path::Path;

use support::{meadow, transcript};

/// Files in `dir`.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("scratch directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_write_that_fails_half_way_leaves_nothing() {
    for (name, args) in [
        ("outputs-render", vec!["render", "--device", support::DEVICE, "--blades", "200", "--size", "32x32", "--out"]),
        ("outputs-export", vec!["keyframes", "--poses", "64", "--segments", "2", "--export"]),
    ] {
        let dir = support::scratch(name);
        let path = &dir.join("x.png");
        // Half-way through the bytes, and at sync_all after all of them (a disk that fills while
        // the page cache is written back: the error must not be lost on drop).
        for (fault, said) in [("1", "no space left (injected)"), ("1:sync", "no space left at sync (injected)")] {
            let output =
                meadow().args(&args).arg(path).env("MEADOW_INJECT_WRITE_FAILURE", fault).output().expect("run");
            assert_eq!(output.status.code(), Some(1), "{fault}: {}", transcript(&output));
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(stderr.starts_with("error: ") && stderr.contains(said) && stderr.lines().count() == 1, "{stderr}");
            assert!(!String::from_utf8_lossy(&output.stdout).contains("wrote"), "{fault}: {}", transcript(&output));
            assert!(!path.exists(), "{fault}: {} was written", path.display());
            assert_eq!(leftovers(&dir), Vec::<String>::new(), "{fault}: temporary files left");
        }
        // The control: without the fault the same command writes the file.
        let output = meadow().args(&args).arg(path).output().expect("run");
        assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
        assert!(image::open(path).is_ok(), "{} is not a whole PNG", path.display());
    }
}

#[test]
fn a_target_that_is_not_a_regular_file_is_refused_before_any_work() {
    let dir = support::scratch("outputs-fifo");
    let fifo = dir.join("pipe.png");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo");
    assert!(made.success());
    for args in [
        vec!["render", "--device", support::DEVICE, "--blades", "200", "--size", "32x32", "--out"],
        vec!["keyframes", "--poses", "64", "--segments", "2", "--export"],
    ] {
        let output = meadow().args(&args).arg(&fifo).output().expect("run");
        assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        // The message names the flag given (`keyframes` has `--export`, not `--out`).
        let flag = args.last().expect("the output flag");
        let expected = format!("error: {flag} {}: exists and is not a regular file", fifo.display());
        assert_eq!(stderr.trim(), expected);
        // Refused up front: nothing was rendered or generated.
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(!stdout.contains("gpu:") && !stdout.contains("wrote"), "{stdout}");
        let kind = std::fs::symlink_metadata(&fifo).expect("still there").file_type();
        assert!(!kind.is_file(), "the FIFO was replaced");
    }
}

/// Exit 2 with one `error:` line naming `expect`, having written nothing into `dir`.
fn refused_up_front(args: &[&str], expect: &str, dir: &Path) {
    let output = meadow().args(args).env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY").output().expect("run");
    assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1 && stderr.contains(expect), "{stderr}");
    assert_eq!(leftovers(dir), Vec::<String>::new(), "{args:?} wrote something");
}

#[test]
fn every_output_path_is_checked_before_any_work() {
    let dir = support::scratch("outputs-early");
    let out = dir.join("run");
    let out = out.to_str().expect("utf-8");
    let missing = "/nonexistent-meadow-dir/x.png";
    let device = ["--device", support::DEVICE];
    // The trace is checked with the rest, before rendering; the output directory is not created.
    let timing: Vec<&str> = ["timing"]
        .iter()
        .chain(&device)
        .chain(&["--blades", "100", "--trace", missing, "--out", out])
        .copied()
        .collect();
    refused_up_front(&timing, "--trace", &dir);
    // Bad input to overhead or bench leaves no empty output directory.
    let overhead: Vec<&str> =
        ["overhead"].iter().chain(&device).chain(&["--blades", "200000000", "--out", out]).copied().collect();
    refused_up_front(&overhead, "--blades 200000000", &dir);
    let bench: Vec<&str> = ["bench"]
        .iter()
        .chain(&device)
        .chain(&["--blades", "200000000", "--segments", "4", "--out", out])
        .copied()
        .collect();
    refused_up_front(&bench, "--blades 200000000", &dir);
    // The viewer's screenshots, given on the command line or in a script, before even the display.
    refused_up_front(&["view", "--screenshot", missing], "--screenshot", &dir);
    let scripts = support::scratch("outputs-early-script");
    let script = scripts.join("s.txt");
    std::fs::write(&script, format!("0 screenshot {missing}\n1 quit\n")).expect("write script");
    refused_up_front(&["view", "--script", script.to_str().expect("utf-8")], "script screenshot", &dir);
}

#[test]
fn a_path_that_names_a_directory_is_refused_before_any_work() {
    // `x.png/` could never be a file: refused with exit 2 before rendering, nothing created.
    let dir = support::scratch("outputs-slash");
    let slash = format!("{}/", dir.join("x.png").display());
    let device = ["--device", support::DEVICE];
    let render: Vec<&str> =
        ["render"].iter().chain(&device).chain(&["--blades", "200", "--out", &slash]).copied().collect();
    refused_up_front(&render, "names a directory", &dir);
    refused_up_front(&["keyframes", "--poses", "64", "--export", &slash], "names a directory", &dir);
    let out = dir.join("run");
    let out = out.to_str().expect("utf-8");
    let timing: Vec<&str> = ["timing"]
        .iter()
        .chain(&device)
        .chain(&["--blades", "100", "--trace", &slash, "--out", out])
        .copied()
        .collect();
    refused_up_front(&timing, "names a directory", &dir);
}

/// A tiny run of a measuring command writing its set into `out` (and, for timing, a trace).
fn measuring(command: &str, out: &Path, trace: &Path) -> Vec<String> {
    let common = ["--device", support::DEVICE, "--size", "32x32", "--frames", "2", "--warmup", "0"];
    let own: &[&str] = match command {
        "bench" => &["--blades", "300", "--segments", "2", "--modes", "static"],
        "overhead" => {
            &["--blades", "300", "--segments", "1", "--strategies", "instanced,per-cluster", "--clusters", "1"]
        }
        _ => &["--blades", "300"],
    };
    let mut args: Vec<String> = [command].iter().chain(&common).chain(own).map(|s| s.to_string()).collect();
    if command == "timing" {
        args.extend(["--trace".into(), trace.display().to_string()]);
    }
    args.extend(["--out".into(), out.display().to_string()]);
    args
}

#[test]
fn a_measuring_command_writes_its_whole_set_or_nothing() {
    // A write failing half-way through the set, at each of its files in turn (the JSON, CSV,
    // chart and trace: the later ones fail after earlier ones were written), leaves none of them
    // and no temporary, and the output directory the run created is gone again.
    for (command, set) in [
        ("bench", &["bench.csv", "bench.json", "bench.png"][..]),
        ("overhead", &["overhead.csv", "overhead.json", "overhead.png"]),
        ("timing", &["timing.json", "timing.png"]),
    ] {
        let dir = support::scratch(&format!("outputs-set-{command}"));
        let (out, trace) = (dir.join("run"), dir.join("trace.json"));
        let files = set.len() + usize::from(command == "timing");
        for n in 1..=files {
            let output = meadow()
                .args(measuring(command, &out, &trace))
                .env("MEADOW_INJECT_WRITE_FAILURE", n.to_string())
                .output()
                .expect("run");
            assert_eq!(output.status.code(), Some(1), "{command}, file {n}: {}", transcript(&output));
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(stderr.starts_with("error: ") && stderr.contains("no space left"), "{command}, file {n}: {stderr}");
            assert_eq!(
                leftovers(&dir),
                Vec::<String>::new(),
                "{command}, file {n}: a half set or a temporary was left"
            );
        }
        // The control: the same command without the fault writes the whole set, and says so.
        let output = meadow().args(measuring(command, &out, &trace)).output().expect("run");
        assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
        let mut written = leftovers(&out);
        written.sort();
        assert_eq!(written, set, "{command}");
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(set.iter().all(|f| stdout.contains(f)), "{command}: the wrote line: {stdout}");
        assert_eq!(trace.exists(), command == "timing", "{command}: the trace");
    }
}

#[test]
fn a_file_of_a_set_that_is_not_a_regular_file_is_refused_before_any_work() {
    // A FIFO where a file of the set goes: exit 2 naming --out before the device is even opened
    // (no `gpu` or timing output), and the FIFO kept.
    for (command, file) in [("bench", "bench.png"), ("overhead", "overhead.csv"), ("timing", "timing.json")] {
        let dir = support::scratch(&format!("outputs-set-fifo-{command}"));
        let out = dir.join("run");
        std::fs::create_dir(&out).expect("output directory");
        let fifo = out.join(file);
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo").success());
        let output = meadow().args(measuring(command, &out, &dir.join("trace.json"))).output().expect("run");
        assert_eq!(output.status.code(), Some(2), "{command}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        let expected = format!("error: --out {}: exists and is not a regular file", fifo.display());
        assert_eq!(stderr.trim(), expected, "{command}");
        assert!(output.stdout.is_empty(), "{command}: work was done: {}", transcript(&output));
        assert!(!std::fs::symlink_metadata(&fifo).expect("still there").is_file(), "{command}: FIFO replaced");
        assert_eq!(leftovers(&out), [file], "{command}");
    }
}

#[test]
fn timing_of_one_frame_is_refused() {
    // One frame has no interval to histogram: refused up front rather than "writing" a chart.
    let dir = support::scratch("outputs-timing-one-frame");
    let out = dir.join("run");
    let args = ["timing", "--device", support::DEVICE, "--blades", "100", "--frames", "1", "--out"];
    let output = meadow().args(args).arg(&out).output().expect("run");
    assert_eq!(output.status.code(), Some(2), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("error: --frames 1: ") && stderr.lines().count() == 1, "{stderr}");
    assert_eq!(leftovers(&dir), Vec::<String>::new());
}

#[test]
fn ctrl_c_stops_a_measuring_command_with_exit_130_and_nothing_written() {
    for (name, command) in [("bench", "bench"), ("overhead", "overhead"), ("timing", "timing")] {
        let dir = support::scratch(&format!("outputs-interrupt-{name}"));
        let out = dir.join("run");
        // Far more frames than the test waits for: only Ctrl-C ends it in time.
        let frames = "10000";
        let child = meadow()
            .args([command, "--device", support::DEVICE, "--blades", "20000", "--frames", frames, "--out"])
            .arg(&out)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("spawn");
        // Past start-up (the handler is installed first thing), into the frames.
        std::thread::sleep(std::time::Duration::from_millis(2500));
        let sent = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
        assert!(sent.success());
        let output = child.wait_with_output().expect("wait");
        assert_eq!(output.status.code(), Some(130), "{name}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(stderr.trim(), "error: interrupted by SIGINT: nothing written", "{name}");
        assert_eq!(leftovers(&dir), Vec::<String>::new(), "{name} left something");
    }
}
