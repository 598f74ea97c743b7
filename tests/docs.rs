//! The documentation cannot drift from the code (issue 31, item 4). No GPU: these read the
//! repository's Markdown and the library's clap definitions (`meadow::cli::command()`).
//!
//! - `docs/cli.md` is what `meadow::cli::reference::markdown` writes today
//!   (`MEADOW_UPDATE_DOCS=1 cargo test --release --test docs`, or `make cli-docs`, rewrites it).

use std::path::Path;

/// The repository's root.
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

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
