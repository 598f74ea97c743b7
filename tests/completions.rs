//! `meadow completions SHELL` through the real binary: a script for each shell that completes
//! every subcommand, and one `error:` line with exit 2 for a shell it does not know.

mod support;

use support::{meadow, transcript};

#[test]
fn each_shell_gets_a_script_naming_every_subcommand() {
    let subcommands: Vec<String> =
        meadow::cli::command().get_subcommands().map(|c| c.get_name().to_string()).filter(|n| n != "help").collect();
    assert!(subcommands.len() >= 8 && subcommands.iter().any(|s| s == "completions"), "{subcommands:?}");
    for (shell, marker) in [("bash", "complete -F"), ("zsh", "#compdef meadow"), ("fish", "complete -c meadow")] {
        let output = meadow().args(["completions", shell]).output().expect("run meadow");
        assert_eq!(output.status.code(), Some(0), "{shell}: {}", transcript(&output));
        assert!(output.stderr.is_empty(), "{shell}: {}", transcript(&output));
        let script = String::from_utf8(output.stdout).expect("UTF-8 script");
        assert!(script.contains(marker), "{shell}: no `{marker}` in the script");
        for sub in &subcommands {
            assert!(script.contains(sub.as_str()), "{shell}: the script does not name `{sub}`");
        }
        // And a flag of a subcommand: the script completes flags, not only the commands.
        assert!(script.contains("frames-in-flight"), "{shell}: no --frames-in-flight");
    }
}

#[test]
fn an_unknown_shell_is_one_error_line() {
    for args in [&["completions", "tcsh"][..], &["completions"][..]] {
        let output = meadow().args(args).output().expect("run meadow");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", transcript(&output));
        let lines: Vec<&str> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{args:?}: one line expected: {}", transcript(&output));
        assert!(lines[0].starts_with("error: "), "{args:?}: {}", lines[0]);
        assert!(output.stdout.is_empty(), "{args:?}: wrote a script");
    }
    let output = meadow().args(["completions", "tcsh"]).output().expect("run meadow");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("tcsh") && stderr.contains("bash"), "names the value and the choices: {stderr}");
}
