//! What a viewer session writes, checked before any work: the exit screenshot, the script's
//! screenshots (each a writable path, no two the same file) and the overlay's capture directory.

use super::{script, ViewerOptions};
use crate::app;
use crate::error::{Error, Result};

/// Check every output `options` names; the first bad one is bad input.
pub(super) fn check(options: &ViewerOptions) -> Result<()> {
    let script_shots = options.script.iter().flat_map(|s| &s.actions).filter_map(|(_, action)| match action {
        script::Action::Screenshot(path) => Some((std::path::Path::new(path.as_str()), "script screenshot")),
        _ => None,
    });
    let shots: Vec<_> = options.screenshot.iter().map(|p| (p.as_path(), "--screenshot")).chain(script_shots).collect();
    for &(path, flag) in &shots {
        app::output::check_output(path, flag)?;
    }
    // Two screenshots to one file: the second would replace the first.
    app::output::check_distinct(shots.iter().map(|&(path, flag)| (flag, path.to_path_buf())))?;
    if let Some(dir) = options.capture_dir.as_ref().filter(|d| !d.is_dir()) {
        return Err(Error::bad_input(format!("--capture-dir {}: not a directory", dir.display())));
    }
    Ok(())
}
