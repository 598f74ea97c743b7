//! The `meadow` command: parses the command line and runs it (see `meadow::cli`).

use std::process::ExitCode;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    match meadow::cli::parse() {
        Ok(cli) => meadow::cli::run(cli),
        Err(code) => code,
    }
}
