//! Checks on the shader sources that need no GPU: the Rust items their comments cite exist (so
//! the comments cannot drift from the code again), the float constants mirrored from Rust have
//! the Rust values, and `build.rs` rejects a `shared.glsl` it does not understand.

use std::path::{Path, PathBuf};

#[path = "../build/shared_glsl.rs"]
mod shared_glsl;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The comment text of every line of `path` (after `//`), with its line number.
fn comments(path: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(path).expect("readable source");
    text.lines().enumerate().filter_map(|(i, line)| line.split_once("//").map(|(_, c)| (i + 1, c.to_owned()))).collect()
}

/// Every `a::b::{c, d}`-style path in `text`, expanded (`a::b::c`, `a::b::d`), as segments.
fn paths(text: &str) -> Vec<Vec<String>> {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let chars: Vec<char> = text.chars().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if !ident(chars[i]) || (i > 0 && ident(chars[i - 1])) {
            i += 1;
            continue;
        }
        // A run of identifiers joined by `::`, possibly ending in a `{x, y}` group.
        let mut segments = Vec::new();
        let mut j = i;
        let mut group = Vec::new();
        loop {
            let start = j;
            while j < chars.len() && ident(chars[j]) {
                j += 1;
            }
            segments.push(chars[start..j].iter().collect::<String>());
            if chars[j..].starts_with(&[':', ':']) {
                j += 2;
                if chars.get(j) == Some(&'{') {
                    let end = j + chars[j..].iter().position(|&c| c == '}').expect("closed group");
                    let inner: String = chars[j + 1..end].iter().collect();
                    group = inner.split(',').map(|s| s.trim().to_owned()).collect();
                    j = end + 1;
                    break;
                }
                if j < chars.len() && ident(chars[j]) {
                    continue;
                }
            }
            break;
        }
        if group.is_empty() {
            if segments.len() > 1 {
                found.push(segments);
            }
        } else {
            for item in group {
                let mut path = segments.clone();
                path.push(item);
                found.push(path);
            }
        }
        i = j.max(i + 1);
    }
    found
}

/// The crate's top-level modules (`pub mod x;` in `src/lib.rs`).
fn crate_modules() -> Vec<String> {
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).expect("src/lib.rs");
    lib.lines().filter_map(|l| l.trim().strip_prefix("pub mod ")?.strip_suffix(';').map(str::to_owned)).collect()
}

/// The file of module `segments` under `src/`, if there is one.
fn module_file(segments: &[String]) -> Option<PathBuf> {
    let base = root().join("src").join(segments.join("/"));
    [base.with_extension("rs"), base.join("mod.rs")].into_iter().find(|p| p.is_file())
}

/// Whether `source` defines `name` as an item (fn, struct, enum, const, static, trait, type, mod).
fn defines(source: &str, name: &str) -> bool {
    source.lines().any(|line| {
        let words: Vec<&str> = line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).collect();
        words.windows(2).any(|w| {
            ["fn", "struct", "enum", "const", "static", "trait", "type", "mod"].contains(&w[0]) && w[1] == name
        })
    })
}

/// Where `path` fails to resolve, or `None`: the longest prefix naming a module
/// file, then every further segment defined in that file.
fn unresolved(path: &[String]) -> Option<String> {
    let mut split = 1;
    while split < path.len() && module_file(&path[..=split]).is_some() {
        split += 1;
    }
    let Some(file) = module_file(&path[..split]) else {
        return Some(format!("no module file for `{}`", path[..split].join("::")));
    };
    let source = std::fs::read_to_string(&file).expect("readable module");
    path[split..]
        .iter()
        .find(|item| !defines(&source, item))
        .map(|item| format!("`{item}` is not defined in {}", file.strip_prefix(root()).unwrap_or(&file).display()))
}

/// Every file under `shaders/` and `tests/shaders/`, folders walked recursively.
fn shader_sources() -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![root().join("shaders"), root().join("tests/shaders")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("shader folder") {
            let path = entry.expect("entry").path();
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

#[test]
fn the_walk_reaches_every_folder_of_both_trees() {
    let files = shader_sources();
    let nested = |tree: &str| {
        files.iter().filter(|f| f.strip_prefix(root().join(tree)).is_ok_and(|r| r.components().count() > 1)).count()
    };
    assert!(nested("shaders") >= 30, "library shaders in folders: {}", nested("shaders"));
    assert!(nested("tests/shaders") >= 8, "test probes in folders: {}", nested("tests/shaders"));
    assert!(files.iter().any(|f| f.ends_with("shaders/common/shared.glsl")));
}

#[test]
fn every_rust_path_cited_by_a_shader_or_build_script_comment_exists() {
    let modules = crate_modules();
    let mut files = shader_sources();
    files.push(root().join("build.rs"));
    files.push(root().join("build/shared_glsl.rs"));
    files.push(root().join("build/scene_set.rs"));
    let (mut checked, mut errors) = (0, Vec::new());
    for file in &files {
        let is_shader = file.starts_with(root().join("shaders")) || file.starts_with(root().join("tests/shaders"));
        for (line, comment) in comments(file) {
            for path in paths(&comment) {
                let at =
                    format!("{}:{line}: `{}`", file.strip_prefix(root()).unwrap_or(file).display(), path.join("::"));
                if !modules.contains(&path[0]) {
                    // Shaders have no paths of their own: a path there must name a crate item.
                    if is_shader {
                        errors.push(format!("{at}: start with a crate module ({})", modules.join(", ")));
                    }
                    continue;
                }
                checked += 1;
                if let Some(problem) = unresolved(&path) {
                    errors.push(format!("{at}: {problem}"));
                }
            }
        }
    }
    assert!(errors.is_empty(), "stale Rust paths in comments:\n{}", errors.join("\n"));
    assert!(checked >= 15, "only {checked} paths found: is the scanner broken?");
}

#[test]
fn the_path_scanner_finds_groups_and_rejects_missing_items() {
    let found = paths("as `keyframes::table::KeyframeTable::{select, blend}` and wind::COLLIDER_PUSH.");
    let joined: Vec<String> = found.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        joined,
        ["keyframes::table::KeyframeTable::select", "keyframes::table::KeyframeTable::blend", "wind::COLLIDER_PUSH"]
    );
    let path = |s: &str| s.split("::").map(str::to_owned).collect::<Vec<_>>();
    assert!(unresolved(&path("render::forces::blade_force")).is_some());
    assert!(unresolved(&path("render::animation::no_such_fn")).is_some());
    assert!(unresolved(&path("render::animation::blade_force")).is_none());
    assert!(unresolved(&path("render::layouts::scene_bindings")).is_none());
}

/// A float constant's value: a literal, or a quotient of two (`4.0 / 3.0`).
fn literal(text: &str) -> f64 {
    let number = |t: &str| t.trim().parse::<f64>().unwrap_or_else(|e| panic!("{t:?}: {e}"));
    match text.split_once('/') {
        Some((a, b)) => number(a) / number(b),
        None => number(text),
    }
}

#[test]
fn float_constants_mirrored_from_rust_have_the_rust_values() {
    // `const float NAME = VALUE; // path::NAME`: the Rust constant must have the same value.
    let mut checked = 0;
    for file in shader_sources() {
        let text = std::fs::read_to_string(&file).expect("shader");
        for (i, line) in text.lines().enumerate() {
            let Some(rest) = line.trim().strip_prefix("const float ") else { continue };
            let Some((definition, comment)) = rest.split_once("//") else { continue };
            let Some((_, value)) = definition.trim().trim_end_matches(';').split_once('=') else { continue };
            let Some(path) = paths(comment).into_iter().next() else { continue };
            let module = module_file(&path[..path.len() - 1]).expect("cited module exists");
            let name = path.last().expect("segments");
            let source = std::fs::read_to_string(&module).expect("module");
            let rust = source
                .lines()
                .find_map(|l| l.trim().strip_prefix(&format!("pub const {name}: f32 = "))?.strip_suffix(';'))
                .unwrap_or_else(|| panic!("{}:{}: no `pub const {name}: f32`", file.display(), i + 1));
            let (glsl, rust) = (literal(value), literal(rust));
            assert_eq!(glsl, rust, "{}:{}: {name}", file.display(), i + 1);
            checked += 1;
        }
    }
    assert!(checked >= 5, "only {checked} mirrored float constants found");
}

#[test]
fn shared_glsl_generates_documented_constants() {
    let path = root().join("shaders/common/shared.glsl");
    let text = std::fs::read_to_string(&path).expect("shared.glsl");
    let rust = shared_glsl::rust_constants(&path, &text).expect("shared.glsl parses");
    assert!(rust.contains("pub const MAX_SEGMENTS: u32 = 16;"), "{rust}");
    assert!(
        rust.contains("#[doc = \"Per-blade pose records written by a blade response's compute pass.\"]\npub const BINDING_POSES: u32 = 0;"),
        "{rust}"
    );
}

#[test]
fn shared_glsl_rejects_what_it_does_not_understand() {
    let path = Path::new("shared.glsl");
    let ok = "// comment\n\n#ifndef MEADOW_SHARED_GLSL\n#define MEADOW_SHARED_GLSL\n#define A 1u // doc\n#endif\n";
    assert!(shared_glsl::rust_constants(path, ok).is_ok());
    for (bad, why) in [
        ("const uint A = 1u;", "not a define"),
        ("#define A 1u", "no doc"),
        ("#define A 1u //", "empty doc"),
        ("#define A 0x10 // hex", "not decimal"),
        ("#define A -1 // negative", "not a u32"),
        ("#define a 1 // lower case", "name"),
        ("#define A (1u << 2) // expression", "expression"),
        ("#define A 1u // first\n#define A 2u // second", "twice"),
        ("#if 0", "conditional"),
    ] {
        let text = format!("// header\n{bad}\n");
        let error = shared_glsl::rust_constants(path, &text).expect_err(why);
        assert!(error.starts_with("shared.glsl:2: ") || error.starts_with("shared.glsl:3: "), "{why}: {error}");
    }
}
