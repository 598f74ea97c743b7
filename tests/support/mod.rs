//! Shared helpers of the integration tests: run the real `meadow` binary on lavapipe with
//! validation and synchronization validation, and fail on any validation message.
#![allow(dead_code)] // each test crate uses a different subset of these helpers

pub mod schema;
pub mod xvfb;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The device every GPU test runs on (goldens are lavapipe pictures).
pub const DEVICE: &str = "llvmpipe";

/// The `meadow` binary built by cargo for this test run.
pub fn meadow() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_meadow"));
    cmd.env_remove("VK_LAYER_PATH");
    cmd
}

/// A scratch directory for this test's outputs under `target/`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch directory");
    dir
}

/// Text of both streams, for assertion messages.
pub fn transcript(output: &Output) -> String {
    format!(
        "exit {:?}\n--- stdout\n{}--- stderr\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// Panic unless the run exited 0, reported `validation: 0 messages`, and printed no message
/// from a layer (the layer's own logger bypasses our counter, so we also scan the text).
pub fn assert_clean(output: &Output) {
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{}", transcript(output));
    assert!(stdout.contains("validation: 0 messages"), "validation did not run:\n{}", transcript(output));
    for text in [&stdout, &stderr] {
        assert!(
            !text.contains("Validation Error")
                && !text.contains("Validation Warning")
                && !text.contains("validation ["),
            "validation message:\n{}",
            transcript(output)
        );
    }
}

/// `meadow render --validation --device llvmpipe ARGS --out OUT`, asserted clean.
pub fn render(args: &[&str], out: &Path) -> Output {
    let output = meadow()
        .arg("render")
        .args(["--validation", "--device", DEVICE])
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("run meadow");
    assert_clean(&output);
    output
}

/// An RGB8 picture.
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Picture {
    pub fn load(path: &Path) -> Picture {
        let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8();
        Picture { width: image.width(), height: image.height(), rgb: image.into_raw() }
    }

    pub fn save(&self, path: &Path) {
        image::save_buffer(path, &self.rgb, self.width, self.height, image::ExtendedColorType::Rgb8)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * self.width + x) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}
