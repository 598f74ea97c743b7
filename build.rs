//! Compiles every `shaders/*.{vert,frag,comp}` to SPIR-V with glslang into `OUT_DIR`.
//!
//! Shared headers (`shaders/*.glsl`) are pulled in with `#include` (GL_GOOGLE_include_directive);
//! glslang's `--depfile` tells us every file a shader read, so cargo re-runs this script when any
//! source or header changes. A compile error fails the build with glslang's own message (file and
//! line); a missing glslang names the Debian package to install.
//!
//! It also writes `OUT_DIR/gpu_constants.rs` from `shaders/shared.glsl`, the one source of truth
//! for the integer constants both sides use (bindings, specialization-constant ids, flag bits,
//! limits); `render::gpu_constants` includes it. The parser is strict: a line it does not
//! understand fails the build with its file and line.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "build/shared_glsl.rs"]
mod shared_glsl;

const STAGES: [&str; 3] = ["vert", "frag", "comp"];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let shader_dir = manifest.join("shaders");
    println!("cargo:rerun-if-changed={}", shader_dir.display());

    embed_git_commit(&manifest);
    let shared = shader_dir.join("shared.glsl");
    let constants = std::fs::read_to_string(&shared)
        .map_err(|e| format!("cannot read {}: {e}", shared.display()))
        .and_then(|text| shared_glsl::rust_constants(&shared, &text))
        .unwrap_or_else(|e| fail(&e));
    std::fs::write(out_dir.join("gpu_constants.rs"), constants)
        .unwrap_or_else(|e| fail(&format!("cannot write gpu_constants.rs: {e}")));

    let glslang = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    let mut sources: Vec<PathBuf> = std::fs::read_dir(&shader_dir)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", shader_dir.display())))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .collect();
    sources.sort();

    let mut failures = Vec::new();
    for source in &sources {
        let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("");
        if source.is_file() && ext == "glsl" {
            println!("cargo:rerun-if-changed={}", source.display());
        }
        if !STAGES.contains(&ext) {
            continue;
        }
        println!("cargo:rerun-if-changed={}", source.display());
        let file_name = source.file_name().and_then(|n| n.to_str()).expect("utf-8 shader name");
        let spv = out_dir.join(format!("{file_name}.spv"));
        let dep = out_dir.join(format!("{file_name}.d"));
        let output = Command::new(&glslang)
            .arg("-V")
            .args(["--target-env", "vulkan1.2"])
            .arg("-g") // debug info: names in validation messages and captures
            .arg(format!("-I{}", shader_dir.display()))
            .arg("--depfile")
            .arg(&dep)
            .arg("-o")
            .arg(&spv)
            .arg(source)
            .output();
        let output = match output {
            Ok(output) => output,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => fail(
                "glslangValidator not found: install the Debian package `glslang-tools` \
                 (sudo apt-get install glslang-tools), or set GLSLANG_VALIDATOR",
            ),
            Err(e) => fail(&format!("cannot run {glslang}: {e}")),
        };
        if !output.status.success() {
            // glslang prints its diagnostics on stdout ("ERROR: path:line: message").
            let mut text = String::from_utf8_lossy(&output.stdout).into_owned();
            text.push_str(&String::from_utf8_lossy(&output.stderr));
            failures.push(format!("{}:\n{}", source.display(), text.trim_end()));
            continue;
        }
        for include in depfile_inputs(&dep) {
            println!("cargo:rerun-if-changed={}", include.display());
        }
    }
    if !failures.is_empty() {
        fail(&format!("shader compilation failed\n{}", failures.join("\n")));
    }
}

/// Set `MEADOW_GIT_COMMIT` to the checked-out commit, and rebuild when it moves.
fn embed_git_commit(manifest: &Path) {
    // The commit goes into bench.json; a build outside git says "unknown".
    if let Ok(out) = Command::new("git").args(["rev-parse", "HEAD"]).current_dir(manifest).output() {
        if out.status.success() {
            println!("cargo:rustc-env=MEADOW_GIT_COMMIT={}", String::from_utf8_lossy(&out.stdout).trim());
        }
    }
    // HEAD names a branch; a commit moves the branch's ref (loose or packed), not HEAD, so watch
    // those too, or the embedded commit goes stale after the first build.
    let git = manifest.join(".git");
    println!("cargo:rerun-if-changed={}", git.join("HEAD").display());
    println!("cargo:rerun-if-changed={}", git.join("packed-refs").display());
    if let Ok(head) = std::fs::read_to_string(git.join("HEAD")) {
        if let Some(reference) = head.trim().strip_prefix("ref: ") {
            println!("cargo:rerun-if-changed={}", git.join(reference).display());
        }
    }
}

/// Inputs listed by a make-style depfile written by glslang (`out: in1 in2 ...`).
fn depfile_inputs(path: &Path) -> Vec<PathBuf> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Vec::new();
    };
    let joined = text.replace("\\\n", " ");
    joined
        .split_once(": ")
        .map(|(_, inputs)| inputs.split_whitespace().map(PathBuf::from).collect())
        .unwrap_or_default()
}

fn fail(message: &str) -> ! {
    for line in message.lines() {
        println!("cargo:warning={line}");
    }
    eprintln!("{message}");
    std::process::exit(1);
}
