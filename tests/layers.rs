//! The shape of the source tree: the renderer library never imports the tools built on it, every
//! source file opens with a module comment, and files and functions stay a size a reader can
//! hold. Reads `src/` as text; no GPU.

use std::path::{Path, PathBuf};

/// The renderer library: these never import a tool.
const RENDERER: [&str; 7] = ["vk", "render", "scene", "keyframes", "wind.rs", "error.rs", "imagediff.rs"];
/// The tools built on the renderer (`src/<name>.rs` or `src/<name>/`).
const TOOLS: [&str; 4] = ["cli", "app", "harness", "viewer"];
/// Most lines of a source file, and of a function.
const MAX_FILE_LINES: usize = 500;
const MAX_FN_LINES: usize = 80;

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `path` (or `path` itself), sorted.
fn rust_files(path: &Path) -> Vec<PathBuf> {
    if path.is_file() {
        return vec![path.to_path_buf()];
    }
    let mut files = Vec::new();
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(path).expect("read dir").map(|e| e.expect("dir entry").path()).collect();
    entries.sort();
    for entry in entries {
        if entry.is_dir() {
            files.extend(rust_files(&entry));
        } else if entry.extension().is_some_and(|e| e == "rs") {
            files.push(entry);
        }
    }
    files
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn relative(path: &Path) -> String {
    path.strip_prefix(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap_or(path).display().to_string()
}

/// The first path segments named after `root::` in `text`: `crate::app::x` gives `app`, and
/// `crate::{app, vk::Device}` gives `app` and `vk`.
fn segments_after<'t>(text: &'t str, root: &str) -> Vec<&'t str> {
    let ident = |s: &'t str| {
        let s = s.trim_start();
        let end = s.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(s.len());
        &s[..end]
    };
    let mut out = Vec::new();
    for (at, _) in text.match_indices(root) {
        // A whole path root: not the tail of a longer identifier (`my_crate::`).
        let before = text[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &text[at + root.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = &group[..group.find('}').unwrap_or(group.len())];
            out.extend(group.split(',').map(ident).filter(|s| !s.is_empty()));
        } else {
            out.push(ident(rest));
        }
    }
    out
}

#[test]
fn the_renderer_never_imports_the_tools() {
    let mut offences = Vec::new();
    for part in RENDERER {
        for file in rust_files(&src().join(part)) {
            let text = read(&file);
            for (n, line) in text.lines().enumerate() {
                for root in ["crate::", "meadow::"] {
                    for segment in segments_after(line, root) {
                        if TOOLS.contains(&segment) {
                            offences.push(format!("{}:{}: {root}{segment}: {}", relative(&file), n + 1, line.trim()));
                        }
                    }
                }
            }
        }
    }
    assert!(
        offences.is_empty(),
        "the renderer library ({RENDERER:?}) must not use the tools ({TOOLS:?}):\n{}",
        offences.join("\n")
    );
}

#[test]
fn the_scanner_sees_grouped_and_nested_paths() {
    assert_eq!(segments_after("use crate::app::write_png;", "crate::"), ["app"]);
    assert_eq!(segments_after("use crate::{harness, vk::Device};", "crate::"), ["harness", "vk"]);
    assert_eq!(segments_after("x(meadow::viewer::run)", "meadow::"), ["viewer"]);
    assert!(segments_after("use other_crate::app;", "crate::").is_empty());
}

#[test]
fn every_source_file_opens_with_a_module_comment() {
    let missing: Vec<String> = rust_files(&src())
        .into_iter()
        .filter(|file| !read(file).starts_with("//!"))
        .map(|file| relative(&file))
        .collect();
    assert!(
        missing.is_empty(),
        "source files without a `//!` module comment on their first line:\n{}",
        missing.join("\n")
    );
}

/// The functions of `text` over `MAX_FN_LINES`, as (line, name, lines). A function runs from its
/// `fn` line to the first line at its indentation that starts with `}`.
fn long_functions(text: &str) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let body = line.trim_start();
        let indent = &line[..line.len() - body.len()];
        let Some(name) = fn_name(body) else { continue };
        if body.trim_end().ends_with(';') {
            continue; // a declaration without a body
        }
        let end = lines[i + 1..]
            .iter()
            .position(|l| l.strip_prefix(indent).is_some_and(|rest| rest.starts_with('}')))
            .map_or(lines.len() - 1, |k| i + 1 + k);
        let length = end - i + 1;
        if length > MAX_FN_LINES {
            out.push((i + 1, name, length));
        }
    }
    out
}

/// The name of the function a line declares (`pub(crate) const unsafe fn name<…>(`), if any.
fn fn_name(line: &str) -> Option<String> {
    let mut rest = line;
    loop {
        rest = rest.trim_start();
        if let Some(r) = rest.strip_prefix("pub") {
            rest = match r.strip_prefix('(') {
                Some(inner) => &inner[inner.find(')')? + 1..],
                None => r,
            };
        } else if let Some(r) = ["const ", "async ", "unsafe ", "default "].iter().find_map(|k| rest.strip_prefix(k)) {
            rest = r;
        } else if let Some(r) = rest.strip_prefix("extern ") {
            let r = r.trim_start();
            rest = match r.strip_prefix('"') {
                Some(abi) => &abi[abi.find('"')? + 1..],
                None => r,
            };
        } else {
            break;
        }
    }
    let name = rest.strip_prefix("fn ")?;
    let end = name.find(|c: char| !(c.is_alphanumeric() || c == '_'))?;
    (end > 0).then(|| name[..end].to_string())
}

#[test]
fn the_size_scanner_measures_functions() {
    let short = "fn a() {\n    x();\n}\n";
    assert!(long_functions(short).is_empty());
    let long = format!("impl X {{\n    pub(crate) fn b(&self) {{\n{}    }}\n}}\n", "        y();\n".repeat(80));
    assert_eq!(long_functions(&long), [(2, "b".to_string(), 82)]);
    assert_eq!(fn_name("pub unsafe extern \"C\" fn c(x: u32) {"), Some("c".into()));
    assert_eq!(fn_name("let f = |x| x;"), None);
}

#[test]
fn files_and_functions_are_a_size_a_reader_can_hold() {
    let mut offences = Vec::new();
    for file in rust_files(&src()) {
        let text = read(&file);
        let lines = text.lines().count();
        if lines > MAX_FILE_LINES {
            offences.push(format!("{}: {lines} lines (at most {MAX_FILE_LINES})", relative(&file)));
        }
        for (line, name, length) in long_functions(&text) {
            offences.push(format!("{}:{line}: fn {name}: {length} lines (at most {MAX_FN_LINES})", relative(&file)));
        }
    }
    assert!(offences.is_empty(), "too long:\n{}", offences.join("\n"));
}
