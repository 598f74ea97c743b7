//! The soak's gate (`scripts/soak.sh`, run by `make test` and `make soak`) judged on stand-in
//! viewers: it passes flat samples and fails growth, a failed viewer and a viewer that printed no
//! samples. (The real viewer's soak runs in `make test`.)

#[path = "support/mod.rs"]
mod support;

use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Command;

/// A stand-in `meadow` that prints `samples` (frame, rss KiB, live objects) and exits `code`.
fn stand_in(dir: &Path, name: &str, samples: &[(u64, u64, u64)], code: i32) -> std::path::PathBuf {
    let mut script = String::from("#!/bin/sh\n");
    for (frame, rss, live) in samples {
        script.push_str(&format!("echo 'sample: frame {frame} rss_kib {rss} live_vulkan_objects {live}'\n"));
    }
    script.push_str(&format!("exit {code}\n"));
    let path = dir.join(name);
    std::fs::write(&path, script).expect("write stand-in");
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    path
}

fn soak(meadow: &Path) -> (Option<i32>, String) {
    let output = Command::new("bash")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/soak.sh"))
        .env("MEADOW", meadow)
        .env("FRAMES", "100")
        .output()
        .expect("run scripts/soak.sh");
    (output.status.code(), String::from_utf8_lossy(&output.stdout).into_owned())
}

#[test]
fn the_soak_passes_flat_samples_and_fails_growth_failures_and_silence() {
    let dir = support::scratch("soak-gate");
    let flat = [(10, 5000, 66), (20, 5000, 66), (100, 5100, 66)];
    let (code, out) = soak(&stand_in(&dir, "flat", &flat, 0));
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("RSS 5000 -> 5100 KiB (100 KiB), live Vulkan objects 66 -> 66"), "{out}");

    let cases = [
        ("grows", vec![(10, 5000, 66), (20, 5000, 66), (100, 9200, 66)], 0, "RSS grew by 4200 KiB"),
        ("leaks", vec![(10, 5000, 66), (20, 5000, 66), (100, 5000, 67)], 0, "live Vulkan objects grew from 66 to 67"),
        ("fails", flat.to_vec(), 1, "the viewer failed"),
        ("silent", Vec::new(), 0, "the viewer failed or printed no samples"),
        ("one", vec![(100, 5000, 66)], 0, "fewer than 2 samples"),
    ];
    for (name, samples, exit, said) in cases {
        let (code, out) = soak(&stand_in(&dir, name, &samples, exit));
        assert_eq!(code, Some(1), "{name}: {out}");
        assert!(out.contains(said), "{name}: expected '{said}' in: {out}");
    }
}
