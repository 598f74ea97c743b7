//! Compiles the GLSL of `shaders/` (the library's) and `tests/shaders/` (the tests' own) to SPIR-V
//! with glslang into `OUT_DIR/spirv/`.
//!
//! Both trees are walked recursively: a folder per concern (`shaders/cull/`, `shaders/blades/`,
//! ...). Every `.vert`, `.frag` and `.comp` file is a shader; `.glsl` files are headers, pulled in
//! with `#include "folder/name.glsl"` (GL_GOOGLE_include_directive, resolved from `shaders/`, so a
//! test's shader includes the library's headers the same way). glslang's `--depfile` tells us
//! every file a shader read, and each one is a `cargo:rerun-if-changed`, as are the folders (a new
//! file). A compile error fails the build with glslang's own message (file and line); a missing
//! glslang names the Debian package to install.
//!
//! Variants by defines: a shader line `// variant NAME: DEFINE DEFINE=VALUE ...` builds the shader
//! a second time with those defines, as `<path>.NAME.spv`. Every shader is built once per backend
//! profile (`vk::profile::Profile`), with `MEADOW_PROFILE_LAVAPIPE` or `MEADOW_PROFILE_GENERIC`
//! defined: `OUT_DIR/spirv/<profile>/<path>[.<variant>].spv`, the tests' under `tests/`. The
//! library embeds its own (`render::shaders`); the tests' are not part of it.
//!
//! Set 0's bindings are numbered here, not by hand (`build/scene_set.rs`): every
//! `layout(SCENE(Name), …)` declaration of both trees is found, the names are numbered, and
//! `OUT_DIR/glsl/generated/scene_set.glsl` (on glslang's include path) defines them. So are the
//! specialization constants' ids (`layout(constant_id = SPEC(NAME))`, `generated/spec_ids.glsl`).
//!
//! It writes `OUT_DIR/scene_shaders.rs`, the library's shaders that read a scene-set declaration
//! (`render::shaders::SCENE`), and `OUT_DIR/gpu_constants.rs` from `shaders/common/shared.glsl`, the one source of
//! truth for the integer constants both sides use (bindings, specialization-constant ids, flag
//! bits, limits); `render::gpu_constants` includes it. The parser is strict: a line it does not
//! understand fails the build with its file and line.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

#[path = "build/scene_set.rs"]
mod scene_set;
#[path = "build/shared_glsl.rs"]
mod shared_glsl;

const STAGES: [&str; 3] = ["vert", "frag", "comp"];

/// The generated header of set 0's binding numbers, under `OUT_DIR/glsl/` (`build/scene_set.rs`).
const SCENE_SET_HEADER: &str = "generated/scene_set.glsl";

/// The generated header of the specialization constants' ids, beside it.
const SPEC_IDS_HEADER: &str = "generated/spec_ids.glsl";

/// The backend profiles, with the define each one's shaders are built with.
const PROFILES: [(&str, &str); 2] = [("lavapipe", "MEADOW_PROFILE_LAVAPIPE"), ("generic", "MEADOW_PROFILE_GENERIC")];

/// One glslang run: a shader, in one profile and variant.
struct Job {
    source: PathBuf,
    spv: PathBuf,
    defines: Vec<String>,
    /// A library shader's path and variant (`blades/blade.frag.coverage`), in its first profile.
    library: Option<String>,
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let shader_dir = manifest.join("shaders");

    embed_git_commit(&manifest);
    let shared = shader_dir.join("common/shared.glsl");
    let constants = std::fs::read_to_string(&shared)
        .map_err(|e| format!("cannot read {}: {e}", shared.display()))
        .and_then(|text| shared_glsl::rust_constants(&shared, &text))
        .unwrap_or_else(|e| fail(&e));
    std::fs::write(out_dir.join("gpu_constants.rs"), constants)
        .unwrap_or_else(|e| fail(&format!("cannot write gpu_constants.rs: {e}")));

    let trees = [
        (shader_dir.clone(), "", walk(&shader_dir)),
        (manifest.join("tests/shaders"), "tests/", walk(&manifest.join("tests/shaders"))),
    ];
    let generated = out_dir.join("glsl");
    let declaring = write_scene_set(&manifest, &generated, &trees);
    let jobs = jobs(&trees, &out_dir);
    let scene = compile_all(&jobs, &[shader_dir, generated], &out_dir, &declaring);
    write_scene_index(&out_dir, scene);
}

/// One compilation per shader stage file of `trees` (`(root, key prefix, files)`), per backend
/// profile and per variant (`variants`, the plain build first); a library shader's key is its
/// path under `shaders/` (with `.variant`), for the lavapipe profile's build.
fn jobs(trees: &[(PathBuf, &str, Vec<PathBuf>)], out_dir: &Path) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (tree, prefix, files) in trees {
        let prefix = *prefix;
        for source in files {
            println!("cargo:rerun-if-changed={}", source.display());
            let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !STAGES.contains(&ext) {
                continue;
            }
            let relative = source.strip_prefix(tree).expect("under its tree").to_str().expect("utf-8 shader path");
            let text = std::fs::read_to_string(source)
                .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", source.display())));
            let variants = variants(&text).unwrap_or_else(|e| fail(&format!("{}: {e}", source.display())));
            for (profile, profile_define) in PROFILES {
                let base = out_dir.join("spirv").join(profile).join(format!("{prefix}{relative}"));
                let named =
                    std::iter::once((None, Vec::new())).chain(variants.iter().map(|(n, d)| (Some(n), d.clone())));
                for (name, mut defines) in named {
                    defines.push(profile_define.to_owned());
                    let key = match name {
                        Some(name) => format!("{relative}.{name}"),
                        None => relative.to_owned(),
                    };
                    let spv = PathBuf::from(format!("{}{}.spv", base.display(), &key[relative.len()..]));
                    let library = (prefix.is_empty() && profile == PROFILES[0].0).then_some(key);
                    jobs.push(Job { source: source.clone(), spv, defines, library });
                }
            }
        }
    }
    jobs
}

/// Compile `jobs` on up to 4 threads (failing the build with every message if any fails), and
/// return the keys of the library's shaders that read a scene-set declaration (a file of
/// `declaring`): the scene shaders whose sets 0 and 1 `render::layouts` unites.
fn compile_all(jobs: &[Job], includes: &[PathBuf], out_dir: &Path, declaring: &[PathBuf]) -> Vec<String> {
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    let glslang = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    let failures = Mutex::new(Vec::new());
    let scene = Mutex::new(Vec::new());
    let queue = Mutex::new(jobs.iter());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(4);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                let Some(job) = queue.lock().expect("queue").next() else { break };
                match compile(&glslang, includes, out_dir, job) {
                    Ok(inputs) => {
                        let reads = |i: &PathBuf| declaring.contains(i) || declaring.contains(&job.source);
                        if let Some(key) = job.library.as_ref().filter(|_| inputs.iter().any(reads)) {
                            scene.lock().expect("scene").push(key.clone());
                        }
                    }
                    Err(message) => failures.lock().expect("failures").push(message),
                }
            });
        }
    });
    let mut failures = failures.into_inner().expect("failures");
    if !failures.is_empty() {
        failures.sort();
        failures.dedup();
        fail(&format!("shader compilation failed\n{}", failures.join("\n")));
    }
    scene.into_inner().expect("scene")
}

/// Write `scene_shaders.rs`: the scene shaders' keys, sorted, as the library includes them.
fn write_scene_index(out_dir: &Path, mut scene: Vec<String>) {
    scene.sort();
    let mut index = String::from(
        "// Generated by build.rs: the library's shaders that read a scene-set declaration, whose sets 0 and 1\n\
         // are the scene's and the animation model's (`render::layouts`).\n&[\n",
    );
    for key in scene {
        index.push_str(&format!("    crate::spirv_shader!(\"{key}\"),\n"));
    }
    index.push_str("]\n");
    std::fs::write(out_dir.join("scene_shaders.rs"), index)
        .unwrap_or_else(|e| fail(&format!("cannot write scene_shaders.rs: {e}")));
}

/// Number set 0's resources and the specialization constants from their declarations in
/// `trees` and write `generated/scene_set.glsl` and `generated/spec_ids.glsl` under `generated`
/// (only when they changed); the library's files that declare a set-0 resource. A bad declaration fails the build with its file and line.
fn write_scene_set(manifest: &Path, generated: &Path, trees: &[(PathBuf, &str, Vec<PathBuf>)]) -> Vec<PathBuf> {
    let (mut declarations, mut constants) = (Vec::new(), Vec::new());
    let mut declaring = Vec::new();
    for (_, prefix, files) in trees {
        for file in files {
            let Ok(text) = std::fs::read_to_string(file) else { continue };
            let shown = file.strip_prefix(manifest).unwrap_or(file).display().to_string();
            let found = scene_set::declarations(&shown, &text, prefix.is_empty()).unwrap_or_else(|e| fail(&e));
            if !found.is_empty() && prefix.is_empty() {
                declaring.push(file.clone());
            }
            declarations.extend(found);
            constants
                .extend(scene_set::spec_declarations(&shown, &text, prefix.is_empty()).unwrap_or_else(|e| fail(&e)));
        }
    }
    let headers =
        [(SCENE_SET_HEADER, scene_set::header(&declarations)), (SPEC_IDS_HEADER, scene_set::spec_header(&constants))];
    for (name, header) in headers {
        let header = header.unwrap_or_else(|e| fail(&e));
        let path = generated.join(name);
        std::fs::create_dir_all(path.parent().expect("in a folder"))
            .unwrap_or_else(|e| fail(&format!("cannot create {}: {e}", path.display())));
        if std::fs::read_to_string(&path).ok().as_deref() != Some(header.as_str()) {
            std::fs::write(&path, header).unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", path.display())));
        }
    }
    declaring
}

/// Every file under `dir`, sorted, folders first watched for new files (`cargo:rerun-if-changed`).
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        println!("cargo:rerun-if-changed={}", folder.display());
        let entries =
            std::fs::read_dir(&folder).unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", folder.display())));
        for entry in entries {
            let path = entry.unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", folder.display()))).path();
            if path.is_dir() {
                folders.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The `// variant NAME: DEFINE DEFINE=VALUE ...` lines of a shader: (name, `-D` arguments).
fn variants(text: &str) -> Result<Vec<(String, Vec<String>)>, String> {
    let mut found: Vec<(String, Vec<String>)> = Vec::new();
    for (index, line) in text.lines().enumerate() {
        let Some(rest) = line.trim().strip_prefix("// variant ") else { continue };
        let at = |why: &str| format!("line {}: {why}: `{line}`", index + 1);
        let (name, defines) = rest.split_once(':').ok_or_else(|| at("a variant is `// variant NAME: DEFINES`"))?;
        let name = name.trim();
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_') {
            return Err(at("a variant's name is lower-case letters, digits and `_`"));
        }
        let defines: Vec<String> = defines.split_whitespace().map(str::to_owned).collect();
        let valid = |d: &String| {
            let name = d.split_once('=').map_or(d.as_str(), |(n, _)| n);
            !name.is_empty() && name.chars().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        };
        if defines.is_empty() || !defines.iter().all(valid) {
            return Err(at("a variant defines one or more NAME or NAME=VALUE, names in upper case"));
        }
        if found.iter().any(|(n, _)| n == name) {
            return Err(at("the variant is named twice"));
        }
        found.push((name.to_owned(), defines));
    }
    Ok(found)
}

/// Compile one job: the files it read, or glslang's message with the shader's path. Files under
/// `out_dir` (the generated header) are not watched: this script writes them.
fn compile(glslang: &str, includes: &[PathBuf], out_dir: &Path, job: &Job) -> Result<Vec<PathBuf>, String> {
    let parent = job.spv.parent().expect("spv in a folder");
    std::fs::create_dir_all(parent).map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    let dep = job.spv.with_extension("d");
    let output = Command::new(glslang)
        .arg("-V")
        .args(["--target-env", "vulkan1.2"])
        .arg("-g") // debug info: names in validation messages and captures
        .args(includes.iter().map(|dir| format!("-I{}", dir.display())))
        .args(job.defines.iter().map(|d| format!("-D{d}")))
        .arg("--depfile")
        .arg(&dep)
        .arg("-o")
        .arg(&job.spv)
        .arg(&job.source)
        .output();
    let output = match output {
        Ok(output) => output,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => fail(
            "glslangValidator not found: install the Debian package `glslang-tools` \
             (sudo apt-get install glslang-tools), or set GLSLANG_VALIDATOR",
        ),
        Err(e) => return Err(format!("cannot run {glslang}: {e}")),
    };
    if !output.status.success() {
        // glslang prints its diagnostics on stdout ("ERROR: path:line: message").
        let mut text = String::from_utf8_lossy(&output.stdout).into_owned();
        text.push_str(&String::from_utf8_lossy(&output.stderr));
        return Err(format!("{} ({}):\n{}", job.source.display(), job.defines.join(" "), text.trim_end()));
    }
    let inputs = depfile_inputs(&dep);
    for include in inputs.iter().filter(|i| !i.starts_with(out_dir)) {
        println!("cargo:rerun-if-changed={}", include.display());
    }
    Ok(inputs)
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
    // those too, or the embedded commit goes stale after the first build. In a worktree, HEAD is
    // in the worktree's git folder and the refs in the common one.
    let git_path = |flag: &str| {
        let out = Command::new("git").args(["rev-parse", flag]).current_dir(manifest).output().ok()?;
        out.status.success().then(|| manifest.join(String::from_utf8_lossy(&out.stdout).trim()))
    };
    let (Some(git), Some(common)) = (git_path("--git-dir"), git_path("--git-common-dir")) else {
        return;
    };
    // A missing file would re-run this script on every build: watch only those that exist.
    let mut watched = vec![git.join("HEAD"), common.join("packed-refs")];
    if let Ok(head) = std::fs::read_to_string(git.join("HEAD")) {
        if let Some(reference) = head.trim().strip_prefix("ref: ") {
            watched.push(common.join(reference));
        }
    }
    for path in watched.iter().filter(|p| p.is_file()) {
        println!("cargo:rerun-if-changed={}", path.display());
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
