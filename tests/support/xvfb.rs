//! An Xvfb server of the test's own, for `meadow view`. Not `xvfb-run`: that script removes a
//! temporary folder of its own at exit and, when that fails, replaces the viewer's exit code with
//! its own 5 (seen once in CI, on a run meadow had refused with 2).

use std::io::BufRead;
use std::process::{Child, Command, Stdio};

/// A running Xvfb (killed on drop) and its display name.
pub struct Xvfb {
    server: Child,
    display: String,
}

impl Xvfb {
    /// Start one with screen 0 of `screen` (`WxHxDEPTH`). `-displayfd` picks a free display and
    /// says which once it accepts clients; `-noreset` keeps it from resetting when a client leaves
    /// (a client arriving during a reset is refused).
    pub fn start(screen: &str) -> Xvfb {
        let mut server = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", screen, "-nolisten", "tcp", "-noreset"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb is installed by the test command (package xvfb)");
        let mut line = String::new();
        std::io::BufReader::new(server.stdout.take().expect("stdout")).read_line(&mut line).expect("display");
        assert!(!line.trim().is_empty(), "Xvfb said no display");
        Xvfb { server, display: format!(":{}", line.trim()) }
    }

    /// `cmd` pointed at this server alone: its DISPLAY, no Wayland, no X authority file (the
    /// server was started without access control).
    pub fn on<'a>(&self, cmd: &'a mut Command) -> &'a mut Command {
        cmd.env("DISPLAY", &self.display).env_remove("WAYLAND_DISPLAY").env_remove("XAUTHORITY")
    }

    /// The display name (`:N`).
    pub fn display(&self) -> &str {
        &self.display
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.server.kill();
        let _ = self.server.wait();
    }
}
