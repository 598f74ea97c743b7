//! The command-line reference (`docs/cli.md`), written from the clap definitions themselves: every
//! subcommand with its usage, and every flag with its value names, default, possible values,
//! conflicts and help text. `tests/docs.rs` regenerates it and fails when the committed file
//! differs, so the reference cannot drift from `meadow --help`.

use std::fmt::Write;

use clap::{Arg, Command};

/// How to regenerate the reference (written into it, and printed by the test that checks it).
pub const REGENERATE: &str = "make cli-docs";

/// The Markdown reference of `command` (the root, `meadow`) and of all its visible subcommands,
/// depth first, in their declaration order.
pub fn markdown(command: &Command) -> String {
    let mut root = command.clone();
    root.build();
    let name = root.get_name().to_string();
    let mut out = String::new();
    let _ = writeln!(out, "# `{name}` command-line reference\n");
    let _ = writeln!(
        out,
        "Generated from the clap definitions in `src/cli/` by `meadow::cli::reference::markdown`; do not edit \
         by hand. After changing a flag or its help, run `{REGENERATE}` (`tests/docs.rs` fails while this file \
         and the parser differ).\n"
    );
    let _ = writeln!(
        out,
        "Every command also takes `-h` (a summary) and `--help` (the whole help); `{name} --version` prints the \
         version. A bad command line is one `error: …` line on standard error and exit code 2.\n"
    );
    let _ = writeln!(
        out,
        "No flag is silently ignored: a flag typed on the command line (not a default) that has no effect in \
         the configuration the rest of the line chooses is refused the same way, before any work, with \
         `error: --flag has no effect with <configuration>: <why>`; for example `--lod-scale` with \
         `--brute-force`, `--density` without `--field`, `--threshold` without `--compare`. The cases are \
         one table, `RULES` in `src/cli/effect/rules.rs`.\n"
    );
    let commands = visible_subcommands(&root);
    if !commands.is_empty() {
        let _ = writeln!(out, "| Command | What it does |\n|---|---|");
        for sub in &commands {
            let path = format!("{name} {}", sub.get_name());
            let _ = writeln!(out, "| [`{path}`](#{}) | {} |", anchor(&path), cell(&first_paragraph(about(sub))));
        }
        out.push('\n');
    }
    section(&mut out, &mut root, &name, 2);
    out
}

/// The section of `command` (called `path` on the command line) at heading `level`, then those of
/// its subcommands one level down.
fn section(out: &mut String, command: &mut Command, path: &str, level: usize) {
    let _ = writeln!(out, "{} `{path}`\n", "#".repeat(level));
    let about = about(command);
    if !about.is_empty() {
        let about = about.trim_end();
        let stop = if about.ends_with(['.', '!', '?']) { "" } else { "." };
        let _ = writeln!(out, "{about}{stop}\n");
    }
    let usage = command.render_usage().to_string();
    let usage = usage.trim().strip_prefix("Usage: ").unwrap_or(usage.trim());
    let _ = writeln!(out, "```text\n{usage}\n```\n");
    let arguments: Vec<&Arg> = command
        .get_arguments()
        .filter(|a| !a.is_hide_set() && !matches!(a.get_id().as_str(), "help" | "version"))
        .collect();
    if !arguments.is_empty() {
        let _ = writeln!(out, "| Argument | Value | Default | Description |\n|---|---|---|---|");
        for arg in arguments {
            let conflicts: Vec<String> = command.get_arg_conflicts_with(arg).iter().map(|a| flag(a)).collect();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} |",
                code(&flag(arg)),
                value(arg),
                default(arg),
                cell(&description(arg, &conflicts))
            );
        }
        out.push('\n');
    }
    let names: Vec<String> = visible_subcommands(command).iter().map(|c| c.get_name().to_string()).collect();
    for name in names {
        let sub = command.find_subcommand_mut(&name).expect("listed above");
        section(out, sub, &format!("{path} {name}"), level + 1);
    }
}

/// The subcommands a user sees (not clap's `help`, nor hidden ones).
fn visible_subcommands(command: &Command) -> Vec<&Command> {
    command.get_subcommands().filter(|c| !c.is_hide_set() && c.get_name() != "help").collect()
}

/// A command's whole description (`about`, or the long one when it has more).
fn about(command: &Command) -> String {
    command.get_long_about().or(command.get_about()).map(ToString::to_string).unwrap_or_default()
}

/// The first paragraph of a text.
fn first_paragraph(text: String) -> String {
    text.split("\n\n").next().unwrap_or_default().trim().to_string()
}

/// `--long` (with `-s, ` before it and visible aliases after it), or `<NAME>` for a positional.
fn flag(arg: &Arg) -> String {
    if arg.is_positional() {
        return format!("<{}>", value_names(arg).join(" "));
    }
    let mut names = Vec::new();
    names.extend(arg.get_short().map(|s| format!("-{s}")));
    names.extend(arg.get_visible_short_aliases().into_iter().flatten().map(|s| format!("-{s}")));
    names.extend(arg.get_long().map(|l| format!("--{l}")));
    names.extend(arg.get_visible_aliases().into_iter().flatten().map(|l| format!("--{l}")));
    names.join(", ")
}

/// The value names of an argument that takes values (clap's default: its id in capitals).
fn value_names(arg: &Arg) -> Vec<String> {
    match arg.get_value_names() {
        Some(names) => names.iter().map(ToString::to_string).collect(),
        None => vec![arg.get_id().as_str().to_uppercase()],
    }
}

/// The value column: the value names (`A,…` when comma-separated, `…` when repeatable), or
/// nothing for a switch.
fn value(arg: &Arg) -> String {
    if !arg.get_action().takes_values() || arg.is_positional() {
        return String::new();
    }
    let mut names = value_names(arg).join(" ");
    if let Some(delimiter) = arg.get_value_delimiter() {
        names.push_str(&format!("{delimiter}…"));
    }
    match arg.get_action() {
        clap::ArgAction::Append if arg.get_value_delimiter().is_none() => format!("{} (repeatable)", code(&names)),
        _ => code(&names),
    }
}

/// The default column.
fn default(arg: &Arg) -> String {
    if !arg.get_action().takes_values() {
        // A switch's `false`.
        return String::new();
    }
    let values: Vec<String> = arg.get_default_values().iter().map(|v| v.to_string_lossy().into_owned()).collect();
    match values.is_empty() {
        true => String::new(),
        false => code(&values.join(",")),
    }
}

/// The help text, then the possible values (with their own help) and the conflicts.
fn description(arg: &Arg, conflicts: &[String]) -> String {
    let mut text = arg.get_long_help().or(arg.get_help()).map(ToString::to_string).unwrap_or_default();
    // clap drops the full stop of a one-paragraph doc comment: sentences follow.
    if !text.is_empty() && !text.trim_end().ends_with(['.', '!', '?']) {
        text = format!("{}.", text.trim_end());
    }
    let possible: Vec<String> = arg
        .get_possible_values()
        .iter()
        .filter(|p| !p.is_hide_set())
        .map(|p| match p.get_help() {
            Some(help) => format!("`{}`: {help}", p.get_name()),
            None => format!("`{}`", p.get_name()),
        })
        .collect();
    if !possible.is_empty() {
        let separator = if possible.iter().any(|p| p.contains(": ")) { "; " } else { ", " };
        text = format!("{} Possible values: {}.", text.trim_end(), possible.join(separator));
    }
    if arg.is_required_set() {
        text = format!("Required. {text}");
    }
    if !conflicts.is_empty() {
        let conflicts: Vec<String> = conflicts.iter().map(|c| format!("`{c}`")).collect();
        text = format!("{} Not with {}.", text.trim_end(), conflicts.join(", "));
    }
    text.trim().to_string()
}

/// A code span in a table cell (`|` escaped).
fn code(text: &str) -> String {
    format!("`{}`", text.replace('|', "\\|"))
}

/// Text made fit for a table cell: paragraphs joined by `<br>`, lines by spaces, `|` escaped.
fn cell(text: &str) -> String {
    let paragraphs: Vec<String> = text
        .split("\n\n")
        .map(|p| p.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|p| !p.is_empty())
        .collect();
    paragraphs.join("<br>").replace('|', "\\|")
}

/// The anchor GitHub gives a heading of `text` in code: lower case, spaces as hyphens.
fn anchor(text: &str) -> String {
    text.to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-')
        .map(|c| match c {
            ' ' => '-',
            c => c,
        })
        .collect()
}
