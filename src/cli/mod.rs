//! The command line of the `meadow` binary: clap's types ([`args`], [`animation`]; their value
//! parsers are [`crate::app::values`], which the viewer's scripts share) and the dispatch of each
//! subcommand to [`crate::app`], [`crate::harness`] or [`crate::viewer`] ([`commands`],
//! [`measure`]). `src/main.rs` only calls [`parse()`] and [`run`].
//! [`command()`] is the parser itself, from which the completion scripts and the reference
//! `docs/cli.md` ([`reference`]) are written.

pub mod animation;
pub mod args;
pub mod commands;
mod culling;
mod default_scene;
mod effect;
pub mod measure;
pub mod reference;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use args::{BenchArgs, CompletionsArgs, GpuArgs, KeyframeArgs, OverheadArgs, RenderArgs, TimingArgs, ViewArgs};

/// A real-time grass renderer on raw Vulkan.
#[derive(Parser)]
#[command(name = "meadow", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Render the grass field headless to a PNG and print what it cost.
    Render(RenderArgs),
    /// Open the interactive viewer (needs a display).
    View(ViewArgs),
    /// Measure static / texture / uniform / floor side by side (thesis Table 6.2), the GPU-driven
    /// cull and LOD against brute force (`--preset lod`), or compare runs.
    Bench(BenchArgs),
    /// Measure draw-submission overhead: the same blades drawn instanced, per cluster, indirectly,
    /// from secondaries recorded on threads, or pre-recorded.
    Overhead(OverheadArgs),
    /// Study a frame's GPU and CPU timing: per-pass percentiles, pipeline statistics, 1/2/3
    /// frames in flight, a frame-time histogram and a Chrome/Perfetto trace.
    Timing(TimingArgs),
    /// List the Vulkan devices with their drivers.
    Devices(GpuArgs),
    /// Generate the keyframe table; report its compression figures and export it as a picture.
    Keyframes(KeyframeArgs),
    /// Print the shell completion script of meadow, e.g. `meadow completions bash >
    /// ~/.local/share/bash-completion/completions/meadow`.
    Completions(CompletionsArgs),
}

impl Command {
    /// Mark a `render` or `view` that draws the default landscape (`default_scene`).
    fn set_landscape(&mut self, landscape: bool) {
        match self {
            Command::Render(args) => args.scene.landscape = landscape,
            Command::View(args) => args.scene.landscape = landscape,
            _ => {}
        }
    }
}

/// The whole command line as clap sees it: what `meadow` parses, and what its completion
/// scripts and `docs/cli.md` ([`reference`]) are written from.
pub fn command() -> clap::Command {
    use clap::CommandFactory;
    Cli::command()
}

/// Parse the process arguments. `--help` and `--version` are printed and give `Err(SUCCESS)`; a
/// bad command line is one `error: …` line on stderr and `Err(2)`: a value clap or a value
/// parser refuses, a `MEADOW_INJECT_*` switch with a bad value (`vk::fault`), or a flag typed
/// where it has no effect ([`effect`]).
pub fn parse() -> Result<Cli, ExitCode> {
    match parse_checked() {
        Ok(cli) => Ok(cli),
        Err(Refused(message)) => {
            eprintln!("error: {message}");
            Err(ExitCode::from(2))
        }
        Err(Clap(e)) => Err(clap_error(e)),
    }
}

/// Why [`parse`] refused the command line.
enum Refusal {
    Clap(clap::Error),
    Refused(String),
}
use Refusal::{Clap, Refused};

/// Clap's parse, then the checks of what it parsed.
fn parse_checked() -> Result<Cli, Refusal> {
    use clap::FromArgMatches;
    let command = command();
    let matches = command.clone().try_get_matches().map_err(Clap)?;
    let mut cli = Cli::from_arg_matches(&matches).map_err(Clap)?;
    if let Some((name, sub)) = matches.subcommand() {
        cli.command.set_landscape(default_scene::draws_landscape(name, sub));
    }
    crate::vk::fault::check_environment().map_err(|e| Refused(e.to_string()))?;
    effect::check(&command, &matches).map_err(Refused)?;
    culling::check_distances(&matches).map_err(Refused)?;
    Ok(cli)
}

/// Print clap's refusal (or its help) and give the exit code.
fn clap_error(e: clap::Error) -> ExitCode {
    match e {
        e if !e.use_stderr() => {
            // --help, --version
            let _ = e.print();
            ExitCode::SUCCESS
        }
        e if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            // `meadow` alone: say what is missing, on one line, with the subcommands.
            let names: Vec<String> =
                command().get_subcommands().map(|c| c.get_name().to_string()).filter(|n| n != "help").collect();
            eprintln!("error: a subcommand is needed: {} (meadow --help)", names.join(", "));
            ExitCode::from(2)
        }
        e => {
            eprintln!("{}", bounded(&one_line(&e.to_string())));
            ExitCode::from(2)
        }
    }
}

/// Clap's message with every long argument it quotes (a value, or the value of `--flag=value`)
/// quoted as every error quotes user text (`error::quoted`): a 100 kB value is not echoed whole.
fn bounded(text: &str) -> String {
    let mut text = text.to_string();
    for arg in std::env::args_os().skip(1) {
        let arg = arg.to_string_lossy();
        for value in [arg.as_ref(), arg.split_once('=').map_or("", |(_, v)| v)] {
            if value.chars().count() > crate::error::QUOTE_CHARS && text.contains(value) {
                text = text.replace(value, &crate::error::quoted(value));
            }
        }
    }
    text
}

/// Clap's error as one line: its first line already reads "error: …"; a missing required
/// argument is listed on the indented lines after it, which are kept (joined), and so is the list
/// of possible values after an invalid one.
fn one_line(text: &str) -> String {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or("error: invalid arguments").trim_end().to_string();
    if !first.ends_with(':') {
        let possible = text.lines().map(str::trim).find(|l| l.starts_with("[possible values:"));
        return possible.map_or(first.clone(), |p| format!("{first} {p}"));
    }
    let listed: Vec<&str> = lines.map(str::trim).take_while(|l| !l.is_empty()).collect();
    format!("{first} {}", listed.join(", "))
}

/// Run the parsed command. The exit code is the command's, or 1 when the validation layer
/// (`--validation`) reported anything, whose message count is printed last.
pub fn run(cli: Cli) -> ExitCode {
    // Every command stops cleanly on SIGINT, SIGTERM and SIGHUP, leaving nothing behind.
    crate::app::interrupt::install();
    let ran = match cli.command {
        Command::Render(args) => Ok(commands::render(args)),
        Command::View(args) => commands::view(args),
        Command::Bench(args) => measure::bench(args).map_err(|e| commands::finish(Err(e))),
        Command::Keyframes(args) => Ok(commands::keyframes(args)),
        Command::Overhead(args) => Ok(measure::overhead(args)),
        Command::Timing(args) => Ok(measure::timing(args)),
        Command::Devices(args) => Ok(commands::devices(args)),
        Command::Completions(args) => Ok(commands::completions(args)),
    };
    let code = match ran {
        Ok((code, validation)) => exit_code(code, validation),
        Err(code) => ExitCode::from(code),
    };
    // A free the allocator refused is a bug the destructors could only log: the run fails.
    match crate::vk::device::free_errors() {
        0 => code,
        n => {
            eprintln!("error: the allocator refused {n} free(s) (logged above)");
            ExitCode::from(1)
        }
    }
}

/// The process exit code of a command that returned `code`, after printing the validation count.
fn exit_code(code: u8, validation: Option<u64>) -> ExitCode {
    match validation {
        Some(count) => {
            println!("validation: {count} messages");
            if count > 0 && code == 0 {
                return ExitCode::from(1);
            }
            ExitCode::from(code)
        }
        None => ExitCode::from(code),
    }
}
