//! The second hardening round (issue 38), each kind through the real binary: two outputs naming
//! one file and a 255-byte output name; window sizes past the device or the platform, before the
//! window exists (Xvfb); inputs that are not regular files or too large; presets past the
//! device's limits; the memory budget with multisampled targets; SIGINT, SIGTERM and SIGHUP in
//! every command; bounded quotes of user input; the address-space limit before the device.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use support::{meadow, scratch, transcript};

/// Names in `dir` (recursively is not needed: nothing may be there at all).
fn leftovers(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("scratch directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Run `cmd`, killed (and the test failed) if it does not end within `limit`: a FIFO or a
/// device must not make meadow hang.
fn within(mut cmd: Command, limit: Duration) -> Output {
    use std::io::Read;
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn");
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            bytes
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("stdout")));
    let stderr = drain(Box::new(child.stderr.take().expect("stderr")));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > limit {
            // Not reaped yet: the handle still names our child.
            let _ = child.kill();
            let _ = child.wait();
            panic!("{cmd:?}: still running after {limit:?}, killed");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Output { status, stdout: stdout.join().expect("stdout"), stderr: stderr.join().expect("stderr") }
}

/// Exit `code` with exactly one `error:` line containing every one of `expect`, no panic.
fn assert_one_line(case: &str, output: &Output, code: i32, expect: &[&str]) {
    assert_eq!(output.status.code(), Some(code), "{case}: {}", transcript(output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{case}: one error line: {stderr}");
    assert!(!stderr.contains("panicked"), "{case}: panic: {stderr}");
    for e in expect {
        assert!(stderr.contains(e), "{case}: no '{e}' in {stderr}");
    }
}

// ---- 1. No output lost ---------------------------------------------------------------------

#[test]
fn two_outputs_naming_one_file_are_refused_before_any_work() {
    let dir = scratch("hardening-same-file");
    let to = dir.join("to");
    let device = ["--device", support::DEVICE, "--blades", "300", "--size", "32x32", "--frames", "2"];
    // The set's folder member, the same name through `..` of a folder that does not exist, and
    // through a symbolic link to the scratch folder.
    std::os::unix::fs::symlink(&dir, dir.join("link")).expect("symlink");
    for trace in [to.join("timing.json"), dir.join("nowhere/../to/timing.json"), dir.join("link/to/timing.json")] {
        let output =
            meadow().arg("timing").args(device).arg("--out").arg(&to).arg("--trace").arg(&trace).output().expect("run");
        assert_one_line(&trace.display().to_string(), &output, 2, &["--out", "--trace", "name the same file"]);
        assert!(output.stdout.is_empty(), "work was done: {}", transcript(&output));
        assert_eq!(leftovers(&dir), ["link"], "{}: something was created", trace.display());
    }
    // The viewer's two screenshots of one file (checked before the display is even looked for).
    let script = dir.join("s.txt");
    std::fs::write(&script, format!("0 screenshot {}\n1 quit\n", dir.join("./shot.png").display())).expect("script");
    let output = meadow()
        .args(["view", "--screenshot"])
        .arg(dir.join("shot.png"))
        .arg("--script")
        .arg(&script)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run");
    assert_one_line("view", &output, 2, &["--screenshot", "script screenshot", "name the same file"]);
    // The control: a trace of its own is written with the set.
    let trace = dir.join("trace.json");
    let output =
        meadow().arg("timing").args(device).arg("--out").arg(&to).arg("--trace").arg(&trace).output().expect("run");
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
    assert!(trace.is_file() && to.join("timing.json").is_file());
}

#[test]
fn an_output_name_of_255_bytes_is_written() {
    let dir = scratch("hardening-long-name");
    let name = format!("{}.png", "n".repeat(251));
    assert_eq!(name.len(), 255);
    let out = dir.join(&name);
    let output = meadow()
        .args(["render", "--device", support::DEVICE, "--blades", "200", "--size", "32x32", "--out"])
        .arg(&out)
        .output()
        .expect("run");
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
    assert!(image::open(&out).is_ok(), "not a whole PNG");
    assert_eq!(leftovers(&dir), [name], "a temporary was left");
}

// ---- 2. Big windows ------------------------------------------------------------------------

/// `meadow view ARGS` (validation on) under an Xvfb of its own, in `dir`.
fn xvfb_view(dir: &Path, args: &[&str]) -> Output {
    let xvfb = support::xvfb::Xvfb::start("1280x1024x24");
    let mut cmd = meadow();
    xvfb.on(&mut cmd)
        .args(["view", "--validation", "--device", support::DEVICE, "--blades", "2000"])
        .args(args)
        .current_dir(dir);
    within(cmd, Duration::from_secs(120))
}

#[test]
fn a_window_past_the_device_or_the_platform_is_refused_before_it_exists() {
    let dir = scratch("hardening-window");
    for size in ["65536x100", "100000x100000", "4294967295x1", "100x16385"] {
        let output = xvfb_view(&dir, &["--size", size]);
        assert_one_line(size, &output, 2, &[&format!("--size {size}"), "maxImageDimension2D"]);
        // Refused before the window: no help text, no frames.
        assert!(!String::from_utf8_lossy(&output.stdout).contains("viewer:"), "{size}: {}", transcript(&output));
    }
    // The control: the device's largest side itself opens (and a frame is rendered).
    let output = xvfb_view(&dir, &["--size", "16384x16", "--frames", "1", "--no-ui"]);
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
}

// ---- 3. Inputs and presets -----------------------------------------------------------------

/// The committed thesis run, cut to its first row (a real bench.json).
fn thesis_row() -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/bench-thesis/bench.json");
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(path).expect("thesis")).expect("JSON");
    doc["rows"] = Value::from(vec![doc["rows"][0].clone()]);
    doc
}

fn compare(a: &Path, b: &Path) -> Command {
    let mut cmd = meadow();
    cmd.args(["bench", "--compare"]).arg(a).arg(b);
    cmd
}

#[test]
fn inputs_that_are_not_regular_files_or_too_large_are_refused() {
    let dir = scratch("hardening-inputs");
    let good = dir.join("good.json");
    std::fs::write(&good, thesis_row().to_string()).expect("write");
    let fifo = dir.join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    let quick = Duration::from_secs(20);
    let output = within(compare(&good, &fifo), quick);
    assert_one_line("compare FIFO", &output, 2, &["--compare", "is a FIFO"]);
    let output = within(compare(Path::new("/dev/zero"), &good), quick);
    assert_one_line("compare /dev/zero", &output, 2, &["--compare /dev/zero", "character device"]);
    let output = within(compare(&dir, &good), quick);
    assert_one_line("compare a directory", &output, 2, &["is a directory"]);
    let mut view = meadow();
    view.arg("view").arg("--script").arg(&fifo).env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
    assert_one_line("script FIFO", &within(view, quick), 2, &["--script", "is a FIFO"]);
    // Past the bound (a sparse file: no disk is used), refused before a byte is read.
    let big = dir.join("big.json");
    std::fs::File::create(&big).expect("create").set_len((64 << 20) + 1).expect("set_len");
    let output = within(compare(&big, &good), quick);
    assert_one_line("compare 64 MiB + 1", &output, 2, &["over the 64.0 MiB meadow reads"]);
    // The control: the same documents as regular files compare (exit 0: no regression).
    let output = within(compare(&good, &good), quick);
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
}

/// `bench --compare A B` as arguments.
fn compare_args<'a>(a: &'a Path, b: &'a Path) -> Vec<&'a std::ffi::OsStr> {
    vec!["bench".as_ref(), "--compare".as_ref(), a.as_os_str(), b.as_os_str()]
}

/// `sh -c 'ulimit -v KIB; exec meadow ARGS'`.
fn under_ulimit(kib: u64, args: &[&std::ffi::OsStr]) -> Command {
    let mut cmd = Command::new("sh");
    cmd.arg("-c").arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\"")).arg(env!("CARGO_BIN_EXE_meadow")).args(args);
    cmd.env_remove("VK_LAYER_PATH");
    cmd
}

#[test]
fn a_compare_of_large_files_under_a_memory_limit_ends_with_an_error_line() {
    let dir = scratch("hardening-compare-ulimit");
    // A real document padded to about 38 MB with frames (what makes a document big).
    let mut doc = thesis_row();
    let frames = doc["rows"][0]["variants"][0]["frames"].as_array().expect("frames").clone();
    let padded: Vec<Value> = frames.iter().cycle().take(70_000).cloned().collect();
    doc["rows"][0]["variants"][0]["frames"] = Value::from(padded);
    let big = dir.join("big.json");
    std::fs::write(&big, doc.to_string()).expect("write");
    assert!(std::fs::metadata(&big).expect("big").len() > 20 << 20);
    let small = dir.join("small.json");
    std::fs::write(&small, thesis_row().to_string()).expect("write");
    let output = within(under_ulimit(300_000, &compare_args(&big, &big)), Duration::from_secs(60));
    assert_one_line("38 MB under 300 MB", &output, 1, &["address space", "ulimit -v 300000"]);
    // The control: small documents compare under the same limit.
    let output = within(under_ulimit(300_000, &compare_args(&small, &small)), Duration::from_secs(60));
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
}

#[test]
fn every_preset_checks_the_device_and_the_budget_before_building() {
    let dir = scratch("hardening-presets");
    let out = dir.join("run");
    for (preset, blades, expect) in [
        ("msaa", "5000000", "maxStorageBufferRange"),
        ("msaa", "4000000000", "maxStorageBufferRange"),
        ("lod", "5000000", "maxStorageBufferRange"),
        ("quick", "4000000000", "maxStorageBufferRange"),
    ] {
        let mut cmd = meadow();
        cmd.args(["bench", "--device", support::DEVICE, "--preset", preset, "--blades", blades, "--out"]).arg(&out);
        let output = within(cmd, Duration::from_secs(60));
        assert_one_line(&format!("{preset} {blades}"), &output, 2, &[expect]);
        assert_eq!(leftovers(&dir), Vec::<String>::new(), "{preset} {blades}: left its output folder");
    }
    // The msaa preset's memory: three renderers with 4x targets at 4096x4096.
    let mut cmd = meadow();
    cmd.args(["bench", "--device", support::DEVICE, "--preset", "msaa", "--size", "4096x4096", "--out"]).arg(&out);
    let output = within(cmd, Duration::from_secs(60));
    assert_one_line("msaa 4096x4096", &output, 2, &["three renderers", "2.0 GiB"]);
    assert_eq!(leftovers(&dir), Vec::<String>::new());
}

// ---- 4. The budget counts multisampled targets ---------------------------------------------

#[test]
fn the_budget_counts_multisampled_targets() {
    let dir = scratch("hardening-msaa-budget");
    let out = dir.join("x.png");
    let mut cmd = meadow();
    cmd.args(["render", "--device", support::DEVICE, "--blades", "1000", "--size", "8192x8192", "--msaa", "4"]);
    cmd.arg("--out").arg(&out);
    let output = within(cmd, Duration::from_secs(60));
    // 8192² × (12 + 4 × 12) bytes of targets: 3.75 GiB, and the scene: against lavapipe's 2 GiB
    // heap (and meadow's 2 GiB budget).
    assert_one_line("8192x8192 --msaa 4", &output, 2, &["--msaa 4", "needs 3.9 GiB", "2.0 GiB"]);
    assert_eq!(leftovers(&dir), Vec::<String>::new());
    // A viewer script's resize past what the multisampled images take, refused (no validation
    // message about an image past maxResourceSize), and the control: a resize that fits runs.
    let script = dir.join("resize.txt");
    std::fs::write(&script, "2 resize 8192x8192\n4 quit\n").expect("script");
    let output = xvfb_view(&dir, &["--size", "128x96", "--msaa", "4", "--script", script.to_str().expect("utf-8")]);
    assert_one_line("resize --msaa 4", &output, 2, &["resize 8192x8192", "--msaa 4"]);
    std::fs::write(&script, "2 resize 160x120\n4 quit\n").expect("script");
    let output = xvfb_view(&dir, &["--size", "128x96", "--msaa", "4", "--script", script.to_str().expect("utf-8")]);
    support::assert_clean(&output);
}

// ---- 6. Signals ----------------------------------------------------------------------------

#[test]
fn sigint_sigterm_and_sighup_leave_nothing_behind_in_any_command() {
    let frames = ["--frames", "10000"];
    let small = ["--device", support::DEVICE, "--blades", "20000", "--size", "96x64"];
    let commands: [(&str, Vec<&str>); 5] = [
        ("render", [&["render"][..], &small[..], &frames[..]].concat()),
        ("bench", [&["bench"][..], &small[..], &frames[..], &["--modes", "static"][..]].concat()),
        ("timing", [&["timing"][..], &small[..], &frames[..]].concat()),
        ("overhead", [&["overhead"][..], &small[..], &frames[..]].concat()),
        (
            "msaa",
            vec![
                "bench",
                "--device",
                support::DEVICE,
                "--preset",
                "msaa",
                "--blades",
                "2000",
                "--size",
                "96x64",
                "--frames",
                "10000",
            ],
        ),
    ];
    for (signal, number) in [("INT", 2), ("TERM", 15), ("HUP", 1)] {
        // The five commands at once, each into a scratch folder of its own.
        let running: Vec<_> = commands
            .iter()
            .map(|(name, args)| {
                let dir = scratch(&format!("hardening-signal-{name}-{signal}"));
                let out = if *name == "render" { dir.join("x.png") } else { dir.join("run") };
                let child = meadow()
                    .args(args)
                    .arg("--out")
                    .arg(&out)
                    .stdout(Stdio::piped())
                    .stderr(Stdio::piped())
                    .spawn()
                    .expect("spawn");
                (name, dir, child)
            })
            .collect();
        // Past start-up, into the frames (none can finish 10 000 of them in time).
        std::thread::sleep(Duration::from_secs(6));
        for (_, _, child) in &running {
            let sent = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status();
            assert!(sent.expect("kill").success());
        }
        for (name, dir, child) in running {
            let output = child.wait_with_output().expect("wait");
            let case = format!("{name} SIG{signal}");
            assert_one_line(&case, &output, 128 + number, &[&format!("interrupted by SIG{signal}: nothing written")]);
            assert_eq!(leftovers(&dir), Vec::<String>::new(), "{case} left something");
        }
    }
}

// ---- 9. Bounded quotes ---------------------------------------------------------------------

#[test]
fn errors_quote_at_most_about_80_characters_of_user_input() {
    let dir = scratch("hardening-quotes");
    // The message around the quote is meadow's own (the ui-click error lists the controls shown).
    let most = 1000;
    let bounded = |case: &str, output: &Output, code: i32, expect: &str| {
        assert_one_line(case, output, code, &[expect]);
        let len = output.stderr.len();
        assert!(len < most, "{case}: {len} bytes of error: {}", String::from_utf8_lossy(&output.stderr));
    };
    // A 10 MB device name in a --compare document.
    let base = thesis_row();
    let mut other = base.clone();
    other["device"] = Value::from("d".repeat(10_000_000));
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    std::fs::write(&a, base.to_string()).expect("write");
    std::fs::write(&b, other.to_string()).expect("write");
    bounded("compare device", &compare(&a, &b).output().expect("run"), 2, "not comparable: device");
    // A 10 MB value the schema refuses (its message quotes the value).
    let mut wrong = base.clone();
    wrong["rows"][0]["blades"] = Value::from("7".repeat(10_000_000));
    std::fs::write(&b, wrong.to_string()).expect("write");
    bounded("compare schema", &compare(&a, &b).output().expect("run"), 2, "not a bench.json");
    // Command-line values (an argument is at most 128 kB): clap's own quote and meadow's.
    let long = "z".repeat(100_000);
    let output = meadow().args(["render", "--blades", &long]).output().expect("run");
    bounded("--blades", &output, 2, "--blades");
    let output = meadow().args(["render", &format!("--size={long}")]).output().expect("run");
    bounded("--size=", &output, 2, "--size");
    let output = meadow().args(["render", "--device", &long, "--out"]).arg(dir.join("x.png")).output().expect("run");
    bounded("--device", &output, 2, "no device name contains it");
    // A path (each component under 255 bytes, 4000 bytes in all).
    let deep: PathBuf = std::iter::once(dir.clone()).chain((0..20).map(|_| PathBuf::from("p".repeat(200)))).collect();
    let output = meadow().args(["keyframes", "--export"]).arg(deep.join("x.png")).output().expect("run");
    bounded("deep path", &output, 2, "does not exist");
    // A 10 MB ui-click label in a viewer script: parsed, then looked for on screen.
    let script = dir.join("click.txt");
    std::fs::write(&script, format!("1 ui-click {}\n3 quit\n", "L".repeat(10_000_000))).expect("script");
    let output = xvfb_view(&dir, &["--size", "320x200", "--script", script.to_str().expect("utf-8")]);
    bounded("ui-click", &output, 2, "no control");
}

// ---- 11. The address-space limit -----------------------------------------------------------

#[test]
fn an_address_space_too_small_for_the_device_is_said_before_creating_it() {
    let dir = scratch("hardening-ulimit");
    let out = dir.join("x.png");
    let args = ["render", "--device", support::DEVICE, "--blades", "2000", "--size", "64x48", "--out"];
    let args: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsStr::new).chain([out.as_os_str()]).collect();
    // Above what creating the instance maps (about 250 MB of address space on lavapipe).
    for kib in [300_000, 400_000, 500_000] {
        let output = within(under_ulimit(kib, &args), Duration::from_secs(60));
        let expect = ["software device llvmpipe", "address space", &format!("ulimit -v {kib} KiB"), "raise the limit"];
        assert_one_line(&format!("ulimit -v {kib}"), &output, 1, &expect);
        assert!(!out.exists());
    }
    // The control: a limit above what the device needs renders.
    let output = within(under_ulimit(2_000_000, &args), Duration::from_secs(120));
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
    assert!(out.is_file());
}
