//! The documentation cannot drift from the code (issue 31, item 4). No GPU: these read the
//! repository's Markdown and the library's clap definitions (`meadow::cli::command()`).
//!
//! - `docs/cli.md` is what `meadow::cli::reference::markdown` writes today
//!   (`MEADOW_UPDATE_DOCS=1 cargo test --release --test docs`, or `make cli-docs`, rewrites it).
//! - Every `meadow …` command of a ```sh block in README.md and docs/*.md is accepted by the real
//!   parser.
//! - Every path README.md and docs/*.md cite exists (the rule: [`cited_paths`]).
//! - README.md stays under [`README_LINES`] lines.

use std::collections::BTreeSet;
use std::path::{Component, Path, PathBuf};

/// The repository's root.
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The longest README.md allowed (issue 31: "at most about 250 lines").
const README_LINES: usize = 260;

/// File extensions that make a code span a path even when its folder is not at the root
/// (`render/renderer.rs`).
const EXTENSIONS: [&str; 13] =
    ["rs", "glsl", "comp", "vert", "frag", "toml", "md", "json", "csv", "png", "sh", "txt", "lock"];

/// README.md and docs/*.md, relative to the root, in order.
fn documents() -> Vec<PathBuf> {
    let mut docs: Vec<PathBuf> = std::fs::read_dir(Path::new(ROOT).join("docs"))
        .expect("read docs/")
        .map(|e| e.expect("docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| p.strip_prefix(ROOT).expect("under the root").to_path_buf())
        .collect();
    docs.sort();
    docs.insert(0, PathBuf::from("README.md"));
    docs
}

fn read(doc: &Path) -> String {
    std::fs::read_to_string(Path::new(ROOT).join(doc)).unwrap_or_else(|e| panic!("read {}: {e}", doc.display()))
}

/// A line of a document: its number (from 1), the info word of the fenced block it is in
/// (`None` outside one; the fence lines themselves are left out) and its text.
fn lines(text: &str) -> Vec<(usize, Option<String>, &str)> {
    let mut fence: Option<(String, String)> = None; // (the fence, the info word)
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let ticks = trimmed.chars().take_while(|&c| c == '`' || c == '~').collect::<String>();
        match &fence {
            None if ticks.len() >= 3 => {
                let info = trimmed[ticks.len()..].split_whitespace().next().unwrap_or("").to_lowercase();
                fence = Some((ticks, info));
                continue;
            }
            Some((open, _)) if ticks.starts_with(open.as_str()) && trimmed[ticks.len()..].trim().is_empty() => {
                fence = None;
                continue;
            }
            _ => {}
        }
        out.push((i + 1, fence.as_ref().map(|f| f.1.clone()), line));
    }
    out
}

#[test]
fn the_cli_reference_is_generated_from_the_parser() {
    let path = Path::new(ROOT).join("docs/cli.md");
    let generated = meadow::cli::reference::markdown(&meadow::cli::command());
    if std::env::var_os("MEADOW_UPDATE_DOCS").is_some() {
        std::fs::write(&path, &generated).expect("write docs/cli.md");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed == generated {
        return;
    }
    let at = committed
        .lines()
        .zip(generated.lines())
        .position(|(a, b)| a != b)
        .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
    panic!(
        "docs/cli.md differs from the parser's definitions from line {}:\n  committed: {}\n  generated: {}\n\
         regenerate it with `{}` (MEADOW_UPDATE_DOCS=1 cargo test --release --test docs) and commit it",
        at + 1,
        committed.lines().nth(at).unwrap_or("(end of file)"),
        generated.lines().nth(at).unwrap_or("(end of file)"),
        meadow::cli::reference::REGENERATE,
    );
}

#[test]
fn the_reference_lists_every_subcommand_and_flag() {
    let text = meadow::cli::reference::markdown(&meadow::cli::command());
    let command = meadow::cli::command();
    for sub in command.get_subcommands().filter(|c| c.get_name() != "help") {
        assert!(text.contains(&format!("### `meadow {}`", sub.get_name())), "{}", sub.get_name());
        assert!(text.contains(&format!("(#meadow-{})", sub.get_name())), "{} in the table", sub.get_name());
        for arg in sub.get_arguments().filter_map(clap::Arg::get_long).filter(|l| *l != "help") {
            assert!(text.contains(&format!("| `--{arg}` |")), "meadow {} --{arg}", sub.get_name());
        }
    }
    // A value name and default, possible values with their help, a cell's `|` escaped, a
    // conflict, a positional.
    assert!(text.contains("| `--size` | `WxH` | `1280x720` |"), "{text}");
    assert!(text.contains("Possible values: `fifo`, `mailbox`, `immediate`."));
    assert!(text.contains("`force`: Force magnitude as colour"));
    assert!(text.contains("| `--device` | `INDEX\\|NAME` |"));
    assert!(text.contains("Not with `--no-ui`."));
    assert!(text.contains("| `<SHELL>` |"));
}

/// Words of a shell line, quotes and backslashes resolved; `None` separates commands (`&&`,
/// `||`, `|`, `;`, `&`). Redirections and their targets, and a `#` comment, are left out.
fn shell_words(line: &str) -> Vec<Option<String>> {
    let mut out: Vec<Option<String>> = Vec::new();
    let mut word: Option<String> = None;
    let mut chars = line.chars().peekable();
    let mut skip_next = false; // the target of a redirection
    let end_word = |word: &mut Option<String>, out: &mut Vec<Option<String>>, skip_next: &mut bool| {
        if let Some(w) = word.take() {
            let redirect = w.trim_start_matches(|c: char| c.is_ascii_digit() || c == '&');
            if *skip_next {
                *skip_next = false;
            } else if redirect.starts_with('>') || redirect.starts_with('<') {
                // `> file` (the target follows), `>file`, `2>&1`.
                *skip_next = redirect.trim_start_matches(['>', '<']).is_empty();
            } else {
                out.push(Some(w));
            }
        }
    };
    while let Some(c) = chars.next() {
        match c {
            '\'' => {
                let w = word.get_or_insert_with(String::new);
                w.extend(chars.by_ref().take_while(|&c| c != '\''));
            }
            '"' => {
                let w = word.get_or_insert_with(String::new);
                while let Some(c) = chars.next() {
                    match c {
                        '"' => break,
                        '\\' => w.extend(chars.next()),
                        c => w.push(c),
                    }
                }
            }
            '\\' => word.get_or_insert_with(String::new).extend(chars.next()),
            '#' if word.is_none() => break,
            ';' | '|' | '&' if !(c == '&' && word.as_deref().is_some_and(|w| w.ends_with('>'))) => {
                end_word(&mut word, &mut out, &mut skip_next);
                if chars.peek() == Some(&c) {
                    chars.next();
                }
                out.push(None);
            }
            c if c.is_whitespace() => end_word(&mut word, &mut out, &mut skip_next),
            c => word.get_or_insert_with(String::new).push(c),
        }
    }
    end_word(&mut word, &mut out, &mut skip_next);
    out
}

/// The `meadow` command lines of a ```sh block's line (continuations joined): each command whose
/// program, after leading `NAME=value` assignments, is `meadow`, `target/release/meadow` (with or
/// without `./`), `cargo run … --`, or a program that runs one (`xvfb-run … meadow …`, `env`,
/// `nice`, `time`, `timeout`); its arguments with `meadow` first.
fn meadow_commands(line: &str) -> Vec<Vec<String>> {
    let words = shell_words(line);
    let mut out = Vec::new();
    for command in words.split(Option::is_none) {
        let mut words = command.iter().flatten().map(String::as_str).skip_while(|w| {
            w.split_once('=').is_some_and(|(name, _)| {
                !name.is_empty() && name.chars().all(|c| c == '_' || c.is_ascii_alphanumeric())
            })
        });
        let meadow = |w: &str| matches!(w, "meadow" | "target/release/meadow" | "./target/release/meadow");
        let args: Vec<String> = match words.next() {
            Some(w) if meadow(w) => words.map(String::from).collect(),
            // A program that runs another: meadow is the first word that names it.
            Some("xvfb-run" | "env" | "nice" | "time" | "timeout") => match words.position(meadow) {
                Some(_) => words.map(String::from).collect(),
                None => continue,
            },
            // `cargo run --example` runs an example program, not meadow.
            Some("cargo")
                if command.iter().flatten().any(|w| w == "run")
                    && !command.iter().flatten().any(|w| w == "--example") =>
            {
                words.skip_while(|w| *w != "--").skip(1).map(String::from).collect()
            }
            _ => continue,
        };
        out.push(std::iter::once("meadow".to_string()).chain(args).collect());
    }
    out
}

#[test]
fn every_documented_command_parses() {
    let mut refused = Vec::new();
    let mut parsed = 0;
    let mut in_readme = 0;
    for doc in documents() {
        let text = read(&doc);
        let shell: Vec<(usize, &str)> = lines(&text)
            .into_iter()
            .filter(|(_, fence, _)| matches!(fence.as_deref(), Some("sh" | "bash" | "shell")))
            .map(|(n, _, line)| (n, line))
            .collect();
        // Continuation lines (`\` at the end) join the line after them.
        let mut joined: Vec<(usize, String)> = Vec::new();
        let mut open = false;
        for (n, line) in shell {
            let line = line.trim().strip_prefix("$ ").unwrap_or(line.trim());
            let (body, continues) = match line.strip_suffix('\\') {
                Some(body) => (body, true),
                None => (line, false),
            };
            match (open, joined.last_mut()) {
                (true, Some((_, previous))) => {
                    previous.push(' ');
                    previous.push_str(body);
                }
                _ => joined.push((n, body.to_string())),
            }
            open = continues;
        }
        for (n, line) in joined {
            for args in meadow_commands(&line) {
                parsed += 1;
                in_readme += usize::from(doc == Path::new("README.md"));
                match meadow::cli::command().try_get_matches_from(&args) {
                    Ok(_) => {}
                    Err(e)
                        if matches!(
                            e.kind(),
                            clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion
                        ) => {}
                    Err(e) => refused.push(format!(
                        "{}:{n}: `{}`: {}",
                        doc.display(),
                        args.join(" "),
                        e.to_string().lines().next().unwrap_or("")
                    )),
                }
            }
        }
    }
    assert!(refused.is_empty(), "commands the parser refuses:\n{}", refused.join("\n"));
    // A README whose examples moved out of ```sh blocks would check nothing.
    assert!(in_readme > 0, "README.md has no `meadow …` command in a ```sh block ({parsed} in docs/)");
}

#[test]
fn shell_lines_are_split_as_a_shell_would() {
    let commands = meadow_commands(
        "LP_NUM_THREADS=2 target/release/meadow render --out 'a b.png' 2>&1 | tee x && cargo run --release -- view # c",
    );
    assert_eq!(commands, vec![vec!["meadow", "render", "--out", "a b.png"], vec!["meadow", "view"]]);
    assert_eq!(meadow_commands("meadow bench > out.txt --frames 3"), vec![vec!["meadow", "bench", "--frames", "3"]]);
    assert!(meadow_commands("make run; cargo build --release").is_empty());
    assert_eq!(
        meadow_commands("xvfb-run -a -s \"-screen 0\" meadow view --no-ui"),
        vec![vec!["meadow", "view", "--no-ui"]]
    );
}

/// Every file and folder of the repository (relative to the root, `/`-separated), outside
/// `.git` and the output folders.
fn repository(outputs: &BTreeSet<String>) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(Path::new(ROOT).join(&dir)).expect("read a folder") {
            let entry = entry.expect("a folder entry");
            let relative = dir.join(entry.file_name());
            let name = relative.to_string_lossy().replace('\\', "/");
            if name == ".git" || outputs.contains(&name) {
                continue;
            }
            if entry.file_type().expect("file type").is_dir() {
                stack.push(relative);
            }
            found.insert(name);
        }
    }
    found
}

/// The outputs a path may name without existing: what `.gitignore` ignores at the root
/// (`/target`, `/tests/out`…), and the default of every `--out` of the CLI (`bench-out`…).
fn output_folders() -> BTreeSet<String> {
    let mut outputs: BTreeSet<String> = read(Path::new(".gitignore"))
        .lines()
        .filter_map(|l| l.trim().strip_prefix('/'))
        .map(|l| l.trim_end_matches('/').to_string())
        .collect();
    let command = meadow::cli::command();
    for sub in command.get_subcommands() {
        for arg in sub.get_arguments().filter(|a| a.get_long() == Some("out")) {
            outputs.extend(arg.get_default_values().iter().map(|v| v.to_string_lossy().into_owned()));
        }
    }
    outputs
}

/// Whether `name` matches `pattern`, whose `*` stands for any run of characters but `/`.
fn matches(pattern: &str, name: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == name,
        Some((head, tail)) => {
            name.starts_with(head)
                && (head.len()..=name.len()).any(|i| !name[head.len()..i].contains('/') && matches(tail, &name[i..]))
        }
    }
}

/// The paths a document cites, with their line, as it wrote them, and whether each is a link
/// (resolved from the document's folder only). The rule:
/// - every Markdown link or picture target (`[…](x)`, `![…](x)`, `<img src="x">`) that is not a
///   URL or an anchor (`#…`): a path from the document's folder;
/// - every word of a `code span` in prose (not in fenced blocks) that looks like a path: it has a
///   `/` and either starts with a top-level entry of the repository (`src/…`, `docs/…`), or ends in
///   `/`, or its file name has an extension of [`EXTENSIONS`] (`render/renderer.rs`); or it is a
///   bare `NAME.md`. Words with a URL scheme, an absolute or home path, a placeholder (`<…>`,
///   `{…}`, `$…`) or a `=` are not paths.
fn cited_paths(text: &str, top_level: &BTreeSet<String>) -> Vec<(usize, String, bool)> {
    let mut out = Vec::new();
    for (n, fence, line) in lines(text) {
        if fence.is_some() {
            continue;
        }
        // Link targets: `](target)` and `src="target"`.
        for (open, close) in [("](", ')'), ("src=\"", '"')] {
            for (i, _) in line.match_indices(open) {
                let rest = &line[i + open.len()..];
                if let Some(end) = rest.find(close) {
                    let target = rest[..end].split_whitespace().next().unwrap_or("");
                    let target = target.split('#').next().unwrap_or("");
                    if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
                        out.push((n, target.to_string(), true));
                    }
                }
            }
        }
        // Code spans: the text between pairs of backticks.
        for (k, span) in line.split('`').enumerate() {
            if k % 2 == 0 {
                continue;
            }
            for word in span.split_whitespace() {
                if word.starts_with('-')
                    || word.contains("://")
                    || word.starts_with(['/', '~', '$'])
                    || word.contains(['<', '>', '{', '}', '$', '=', '(', ')'])
                {
                    continue;
                }
                let first = word.split('/').next().unwrap_or("");
                let file = file_part(word).rsplit('/').next().unwrap_or("");
                let extension = file.rsplit_once('.').map(|(_, e)| e).unwrap_or("");
                let pathlike = word.contains('/')
                    && (top_level.contains(first) || word.ends_with('/') || EXTENSIONS.contains(&extension));
                if pathlike || (!word.contains('/') && extension == "md" && file.len() > 3) {
                    out.push((n, word.to_string(), false));
                }
            }
        }
    }
    out
}

/// A path without its `:LINE`, `:LINE-LINE`, `:LINE:COLUMN` or `#L…` suffix (such references are
/// checked for the file only).
fn file_part(path: &str) -> &str {
    let path = path.split("#L").next().unwrap_or(path);
    let mut end = path.len();
    while let Some((head, tail)) = path[..end].rsplit_once(':') {
        if tail.is_empty() || !tail.chars().all(|c| c.is_ascii_digit() || c == '-') {
            break;
        }
        end = head.len();
    }
    &path[..end]
}

/// `path` with `.` and `..` resolved, from the root; `None` when it leaves the repository.
fn normalise(path: &Path) -> Option<String> {
    let mut parts: Vec<String> = Vec::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                parts.pop()?;
            }
            Component::Normal(part) => parts.push(part.to_string_lossy().into_owned()),
            _ => return None,
        }
    }
    Some(parts.join("/"))
}

#[test]
fn every_cited_path_exists() {
    let outputs = output_folders();
    let files = repository(&outputs);
    let top_level: BTreeSet<String> = files.iter().filter(|f| !f.contains('/')).cloned().collect();
    let mut missing = Vec::new();
    let mut checked = 0;
    for doc in documents() {
        let folder = doc.parent().unwrap_or(Path::new(""));
        for (n, cited, link) in cited_paths(&read(&doc), &top_level) {
            checked += 1;
            let path = file_part(&cited).trim_end_matches('/');
            let from_folder = normalise(&folder.join(path));
            let Some(from_folder) = from_folder else {
                missing.push(format!(
                    "{}:{n}: `{cited}` is outside the repository (a clone has nothing there)",
                    doc.display()
                ));
                continue;
            };
            // An output (`bench-out/…`, `target/…`): made by a command, not committed.
            let output = |p: &str| outputs.iter().any(|o| p == o || p.starts_with(&format!("{o}/")));
            let mut candidates = vec![from_folder];
            if !link {
                candidates.extend(normalise(Path::new(path)));
            }
            let found = candidates.iter().any(|c| {
                output(c)
                    || files.iter().any(|f| matches(c, f))
                    // A path from inside the tree (`render/renderer.rs`): the end of one that exists.
                    || (!link && files.iter().any(|f| f.rsplit_once('/').is_some() && (0..f.len()).any(|i| {
                        f.as_bytes()[i] == b'/' && matches(c, &f[i + 1..])
                    })))
            });
            if !found {
                missing.push(format!("{}:{n}: `{cited}` does not exist in the repository", doc.display()));
            }
        }
    }
    assert!(missing.is_empty(), "cited paths that do not exist:\n{}", missing.join("\n"));
    assert!(checked > 0, "no path cited in README.md or docs/*.md: the rule matches nothing");
}

#[test]
fn the_path_rule_finds_what_it_should() {
    let top: BTreeSet<String> = ["src", "docs"].iter().map(|s| s.to_string()).collect();
    let text = "see `src/vk/sync.rs:40` and `render/renderer.rs`, ![x](docs/a.png), `texture/blade`, \
                `T/N`, `--out bench-out`, `passes/`, `http://a/b.rs`, `papers.md`\n```sh\nmeadow `src/no.rs`\n```\n";
    let cited: Vec<String> = cited_paths(text, &top).into_iter().map(|c| c.1).collect();
    assert_eq!(cited, ["docs/a.png", "src/vk/sync.rs:40", "render/renderer.rs", "passes/", "papers.md"]);
    assert_eq!(file_part("src/a.rs:10-20"), "src/a.rs");
    assert_eq!(file_part("src/a.rs:3:7"), "src/a.rs");
    assert!(matches("shaders/cull*.comp", "shaders/cull_tiles.comp") && !matches("a/*.rs", "a/b/c.rs"));
    assert_eq!(normalise(Path::new("../shared/seeds")), None);
}

#[test]
fn the_readme_stays_short() {
    let lines = read(Path::new("README.md")).lines().count();
    assert!(
        lines <= README_LINES,
        "README.md has {lines} lines, over {README_LINES}: move detail into docs/ (issue 31)"
    );
}
