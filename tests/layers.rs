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

/// The crate's modules, lowest first: a module may use only the modules before it. `render`'s
/// direct submodules are placed one by one (their own submodules go with them); `render` itself
/// (its `mod.rs`, which re-exports) sits above them, and the tools above the renderer library.
/// A new module is placed here, or the test fails.
const ORDER: &[&str] = &[
    "error",
    "vk",
    "imagediff",
    "wind",
    "scene",
    "keyframes",
    "render::gpu_constants",
    "render::uniforms",
    "render::limits",
    "render::shaders",
    "render::specialization",
    "render::target",
    "render::submission",
    "render::msaa",
    "render::budget",
    "render::camera_grid",
    "render::terrain_chunks",
    "render::ground_clipmap",
    "render::ground",
    "render::field_gpu",
    "render::draw_rows",
    "render::far_rings",
    "render::culling",
    "render::occlusion",
    "render::cull_reference",
    "render::graph",
    "render::frame",
    "render::overlay",
    "render::recording",
    "render::scene_gpu",
    "render::animation",
    "render::wind",
    "render::settings",
    "render::layouts",
    "render::passes",
    "render::draw_class",
    "render::flowers",
    "render::far_field",
    "render::renderer",
    "render",
    "app",
    "harness",
    "viewer",
    "cli",
];

/// A token of Rust source, comments, strings and character literals left out.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Tok<'t> {
    Ident(&'t str),
    /// `::`
    Colons,
    Open,
    Close,
    Comma,
    Star,
    /// Any other punctuation.
    Other,
}

/// The tokens of `text` with their lines.
fn tokens(text: &str) -> Vec<(usize, Tok<'_>)> {
    let b = text.as_bytes();
    let (mut i, mut line, mut out) = (0, 1, Vec::new());
    // The end of the quoted literal opened at `at` (after its closing quote), counting lines.
    let quoted = |mut at: usize, quote: u8, line: &mut usize| {
        at += 1;
        while at < b.len() && b[at] != quote {
            if b[at] == b'\\' {
                at += 1;
            }
            if b.get(at) == Some(&b'\n') {
                *line += 1;
            }
            at += 1;
        }
        at + 1
    };
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        match c {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'/' if next == Some(b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if next == Some(b'*') => {
                let mut depth = 0;
                while i < b.len() {
                    if b[i..].starts_with(b"/*") {
                        depth += 1;
                        i += 2;
                    } else if b[i..].starts_with(b"*/") {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        line += usize::from(b[i] == b'\n');
                        i += 1;
                    }
                }
            }
            b'"' => i = quoted(i, b'"', &mut line),
            b'\'' => {
                // A character literal ('x', '\n', '\u{..}') or a lifetime ('a).
                let width = text[i + 1..].chars().next().map_or(1, char::len_utf8);
                if next == Some(b'\\') {
                    i = quoted(i, b'\'', &mut line);
                } else if b.get(i + 1 + width) == Some(&b'\'') {
                    i += width + 2;
                } else {
                    i += 1;
                }
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                    i += 1;
                }
                let ident = &text[start..i];
                let hashes = b[i..].iter().take_while(|&&h| h == b'#').count();
                if matches!(ident, "r" | "br") && b.get(i + hashes) == Some(&b'"') {
                    // A raw string: to the quote followed by as many hashes.
                    let close = [&b"\""[..], &vec![b'#'; hashes]].concat();
                    let body = i + hashes + 1;
                    let end = b[body..]
                        .windows(close.len())
                        .position(|w| w == close.as_slice())
                        .map_or(b.len(), |k| body + k);
                    line += b[i..end].iter().filter(|&&x| x == b'\n').count();
                    i = end + close.len();
                } else if ident == "b" && matches!(b.get(i), Some(b'"') | Some(b'\'')) {
                    i = quoted(i, b[i], &mut line);
                } else {
                    out.push((line, Tok::Ident(ident)));
                }
            }
            b':' if next == Some(b':') => {
                out.push((line, Tok::Colons));
                i += 2;
            }
            c if c.is_ascii_whitespace() => i += 1,
            _ => {
                out.push((
                    line,
                    match c {
                        b'{' => Tok::Open,
                        b'}' => Tok::Close,
                        b',' => Tok::Comma,
                        b'*' => Tok::Star,
                        _ => Tok::Other,
                    },
                ));
                i += 1;
            }
        }
    }
    out
}

/// The paths of the use tree at `toks[i..]` under `prefix` (`a::{b, c::d}` gives `a::b` and
/// `a::c::d`; a glob gives its prefix), and where the tree ends.
fn use_tree<'t>(toks: &[(usize, Tok<'t>)], mut i: usize, prefix: Vec<&'t str>) -> (Vec<Vec<&'t str>>, usize) {
    match toks.get(i).map(|t| t.1) {
        Some(Tok::Ident(name)) => {
            let mut path = prefix;
            path.push(name);
            match (toks.get(i + 1).map(|t| t.1), toks.get(i + 2).map(|t| t.1)) {
                (Some(Tok::Colons), _) => use_tree(toks, i + 2, path),
                // `name as alias`
                (Some(Tok::Ident("as")), Some(Tok::Ident(_))) => (vec![path], i + 3),
                _ => (vec![path], i + 1),
            }
        }
        Some(Tok::Open) => {
            let mut paths = Vec::new();
            i += 1;
            while let Some(&(_, tok)) = toks.get(i) {
                if tok == Tok::Close {
                    i += 1;
                    break;
                }
                let (more, end) = use_tree(toks, i, prefix.clone());
                paths.extend(more);
                i = end + usize::from(toks.get(end).map(|t| t.1) == Some(Tok::Comma));
                if end == i && toks.get(i).map(|t| t.1) != Some(Tok::Close) {
                    i += 1; // something a use tree does not hold: step over it
                }
            }
            (paths, i)
        }
        Some(Tok::Star) => (vec![prefix], i + 1),
        _ => (vec![prefix], i),
    }
}

/// Every path of `text` that starts at `crate::`, `super::` or `self::`, made absolute (module
/// segments from the crate root) for a file of module `module`, with its line. Inline modules
/// (`mod tests { … }`) are followed, so their `super::` is the file's module.
fn absolute_paths(text: &str, module: &[String]) -> Vec<(usize, Vec<String>)> {
    let toks = tokens(text);
    let mut out = Vec::new();
    let (mut depth, mut inline): (usize, Vec<(usize, &str)>) = (0, Vec::new());
    let mut i = 0;
    while i < toks.len() {
        let (line, tok) = toks[i];
        match tok {
            Tok::Open => depth += 1,
            Tok::Close => {
                if inline.last().is_some_and(|&(d, _)| d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            Tok::Ident("mod") => {
                if let (Some((_, Tok::Ident(name))), Some((_, Tok::Open))) = (toks.get(i + 1), toks.get(i + 2)) {
                    inline.push((depth + 1, name));
                }
            }
            Tok::Ident(root @ ("crate" | "super" | "self")) if toks.get(i + 1).map(|t| t.1) == Some(Tok::Colons) => {
                let here: Vec<&str> = module.iter().map(String::as_str).chain(inline.iter().map(|m| m.1)).collect();
                let (paths, end) = use_tree(&toks, i + 2, vec![root]);
                for path in paths {
                    out.push((line, resolve(&here, &path)));
                }
                i = end;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// `path` (starting at `crate`, `super` or `self`) seen from module `here`, from the crate root.
fn resolve(here: &[&str], path: &[&str]) -> Vec<String> {
    let mut at: Vec<&str> = match path[0] {
        "crate" => Vec::new(),
        _ => here.to_vec(),
    };
    for (k, &segment) in path.iter().enumerate() {
        match segment {
            "crate" if k == 0 => {}
            "self" => {}
            "super" => {
                at.pop();
            }
            _ => at.push(segment),
        }
    }
    at.into_iter().map(String::from).collect()
}

/// The module of a source file under `src/` (`render/passes/cull/mod.rs` is `render::passes::cull`).
fn module_of(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src()).expect("under src");
    let mut parts: Vec<String> = rel.with_extension("").iter().map(|s| s.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// Whether `module` (segments from the crate root) is a module of the source tree.
fn is_module(module: &[String]) -> bool {
    let path = module.iter().fold(src(), |p, s| p.join(s));
    path.is_dir() || path.with_extension("rs").is_file()
}

/// The names `file` re-exports (`pub use child::{A, B}`) with the child module each comes from.
fn reexports(file: &Path) -> Vec<(String, String)> {
    let text = read(file);
    let toks = tokens(&text);
    let mut out = Vec::new();
    for k in 0..toks.len().saturating_sub(1) {
        if (toks[k].1, toks[k + 1].1) == (Tok::Ident("pub"), Tok::Ident("use")) {
            for path in use_tree(&toks, k + 2, Vec::new()).0 {
                if let (Some(first), Some(last)) = (path.first(), path.last()) {
                    out.push((last.to_string(), first.to_string()));
                }
            }
        }
    }
    out
}

/// What paths from the crate root name besides modules: the names the crate root and `render`
/// re-export (with the child module each comes from), and the exported macros (`crate::name`,
/// with the module that defines each).
struct Names {
    lib: Vec<(String, String)>,
    render: Vec<(String, String)>,
    macros: Vec<(String, Vec<String>)>,
}

impl Names {
    fn read() -> Self {
        let mut macros = Vec::new();
        for file in rust_files(&src()) {
            let text = read(&file);
            let toks = tokens(&text);
            for w in toks.windows(3) {
                if let [(_, Tok::Ident("macro_rules")), (_, Tok::Other), (_, Tok::Ident(name))] = w {
                    macros.push((name.to_string(), module_of(&file)));
                }
            }
        }
        Self { lib: reexports(&src().join("lib.rs")), render: reexports(&src().join("render/mod.rs")), macros }
    }

    /// The entry of `ORDER` a module belongs to (`render::passes::cull` to `render::passes`),
    /// names resolved to the module they come from; `None` for the crate root, an error for a
    /// path to nothing known.
    fn layer_of(&self, module: &[String]) -> Result<Option<String>, String> {
        let through =
            |names: &[(String, String)], name: &str| names.iter().find(|(n, _)| n == name).map(|(_, m)| m.clone());
        match module {
            [] => Ok(None),
            [top] if top == "render" => Ok(Some("render".into())),
            [top, sub, ..] if top == "render" => {
                if is_module(&module[..2]) {
                    Ok(Some(format!("render::{sub}")))
                } else {
                    through(&self.render, sub).map(|m| Some(format!("render::{m}"))).ok_or(format!("render::{sub}"))
                }
            }
            [top, ..] if is_module(&module[..1]) => Ok(Some(top.clone())),
            [top, ..] => match (through(&self.lib, top), self.macros.iter().find(|(n, _)| n == top)) {
                (Some(m), _) => Ok(Some(m)),
                (None, Some((_, defined))) => self.layer_of(defined),
                (None, None) => Err(top.clone()),
            },
        }
    }
}

/// Every use of one module by another in the library: (file, line, user's entry in `ORDER` or
/// module, used module's), the used paths resolved from the crate root.
fn module_uses() -> Vec<(String, usize, Vec<String>, Vec<String>)> {
    let mut out = Vec::new();
    for file in rust_files(&src()) {
        if file.file_name().is_some_and(|n| n == "main.rs") {
            continue; // the binary: a crate of its own
        }
        let module = module_of(&file);
        for (line, path) in absolute_paths(&read(&file), &module) {
            out.push((relative(&file), line, module.clone(), path));
        }
    }
    out
}

#[test]
fn no_module_uses_one_above_it() {
    let names = Names::read();
    let rank = |layer: &str| ORDER.iter().position(|&l| l == layer);
    let mut offences = Vec::new();
    for layer in ORDER {
        let module: Vec<String> = layer.split("::").map(String::from).collect();
        if !is_module(&module) {
            offences.push(format!("ORDER names {layer}, which is no module of src/"));
        }
    }
    for (file, line, module, path) in module_uses() {
        let (user, used) = match (names.layer_of(&module), names.layer_of(&path)) {
            (Ok(Some(user)), Ok(Some(used))) => (user, used),
            (Ok(_), Ok(None)) | (Ok(None), _) => continue,
            (Err(bad), _) | (_, Err(bad)) => {
                offences.push(format!("{file}:{line}: {} names no module ({bad})", path.join("::")));
                continue;
            }
        };
        match (rank(&user), rank(&used)) {
            (_, _) if user == used => {}
            (Some(u), Some(t)) if t < u => {}
            (Some(_), Some(_)) => {
                offences.push(format!("{file}:{line}: {user} uses {}, which lies above it", path.join("::")))
            }
            (None, _) => offences.push(format!("{file}: module {user} is not placed in ORDER")),
            (_, None) => offences.push(format!("{file}:{line}: module {used} is not placed in ORDER")),
        }
    }
    offences.sort();
    offences.dedup();
    assert!(offences.is_empty(), "the layers run one way ({}):\n{}", ORDER.join(" < "), offences.join("\n"));
}

/// The strongly connected components of more than one node of `edges` (Tarjan).
fn cycles(edges: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'g> {
        edges: &'g std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
        index: std::collections::HashMap<&'g str, (usize, usize)>,
        stack: Vec<&'g str>,
        found: Vec<Vec<String>>,
    }
    impl<'g> Walk<'g> {
        fn visit(&mut self, v: &'g str) -> usize {
            let n = self.index.len();
            self.index.insert(v, (n, n));
            self.stack.push(v);
            let mut low = n;
            for w in self.edges.get(v).into_iter().flatten() {
                let w = w.as_str();
                match self.index.get(w) {
                    None => low = low.min(self.visit(w)),
                    Some(&(i, _)) if self.stack.contains(&w) => low = low.min(i),
                    Some(_) => {}
                }
            }
            self.index.insert(v, (n, low));
            if low == n {
                let at = self.stack.iter().position(|&s| s == v).expect("on the stack");
                let component: Vec<String> = self.stack.drain(at..).map(String::from).collect();
                if component.len() > 1 {
                    self.found.push(component);
                }
            }
            low
        }
    }
    let mut walk = Walk { edges, index: Default::default(), stack: Vec::new(), found: Vec::new() };
    for v in edges.keys() {
        if !walk.index.contains_key(v.as_str()) {
            walk.visit(v);
        }
    }
    walk.found
}

#[test]
fn no_render_submodules_use_each_other_in_a_circle() {
    // Between siblings at every depth under `render` (its direct submodules, and e.g. the
    // animation models): a module's use of a sibling's item is an arrow between the two.
    use std::collections::{BTreeMap, BTreeSet};
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut sites: BTreeMap<(String, String), String> = BTreeMap::new();
    for (file, line, module, path) in module_uses() {
        let common = module.iter().zip(&path).take_while(|(a, b)| a == b).count();
        if common == 0 || module[0] != "render" || common >= module.len() || common >= path.len() {
            continue; // outside render, or a use of an ancestor or a descendant
        }
        if !is_module(&path[..=common]) {
            continue; // an item of the common parent
        }
        let (from, to) = (module[..=common].join("::"), path[..=common].join("::"));
        sites.entry((from.clone(), to.clone())).or_insert(format!("{file}:{line}"));
        edges.entry(from).or_default().insert(to);
    }
    assert!(edges.len() > 10, "the scan found only {} modules using a sibling", edges.len());
    let found: Vec<String> = cycles(&edges)
        .into_iter()
        .map(|component| {
            let arrows: Vec<String> = sites
                .iter()
                .filter(|((a, b), _)| component.contains(a) && component.contains(b))
                .map(|((a, b), at)| format!("  {a} -> {b} ({at})"))
                .collect();
            format!("{}:\n{}", component.join(", "), arrows.join("\n"))
        })
        .collect();
    assert!(found.is_empty(), "render's submodules use each other in a circle:\n{}", found.join("\n"));
}

#[test]
fn the_path_scanner_resolves_trees_inline_modules_and_skips_literals() {
    let module = |m: &str| m.split("::").map(String::from).collect::<Vec<_>>();
    let paths = |text: &str, m: &str| -> Vec<String> {
        absolute_paths(text, &module(m)).into_iter().map(|(_, p)| p.join("::")).collect()
    };
    assert_eq!(
        paths("use crate::{app, vk::{Device, buffer::Buffer as B}};", "render::graph"),
        ["app", "vk::Device", "vk::buffer::Buffer"]
    );
    assert_eq!(
        paths("let x = super::super::passes::FloorPass::new();", "render::animation::model"),
        ["render::passes::FloorPass::new"]
    );
    assert_eq!(
        paths(
            "fn f() {}\n#[cfg(test)]\nmod tests {\n    use super::*;\n    use super::super::x::Y;\n}\nuse self::z::W;",
            "render::culling"
        ),
        ["render::culling", "render::x::Y", "render::culling::z::W"]
    );
    assert_eq!(
        paths(
            "// crate::app::x\n/* crate::cli /* nested */ crate::viewer */ let s = \"crate::harness\"; let r = r#\"crate::{\"#; let c = '{'; let l: &'static str = x; pub(crate) fn g<'a>(_: &'a u8) { crate::vk::Device }",
            "scene"
        ),
        ["vk::Device"]
    );
    let lines: Vec<usize> =
        absolute_paths("\"a\nb\"\n/* \n */ crate::vk::X", &module("scene")).into_iter().map(|(l, _)| l).collect();
    assert_eq!(lines, [4]);
    let graph = |arrows: &[(&str, &str)]| {
        let mut g = std::collections::BTreeMap::<String, std::collections::BTreeSet<String>>::new();
        for (a, b) in arrows {
            g.entry(a.to_string()).or_default().insert(b.to_string());
        }
        g
    };
    assert!(cycles(&graph(&[("a", "b"), ("b", "c"), ("a", "c")])).is_empty());
    let mut found = cycles(&graph(&[("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]));
    found[0].sort();
    assert_eq!(found, [["a", "b", "c"]]);
}
