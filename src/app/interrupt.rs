//! Ctrl-C (SIGINT) for the long-running commands: the handler only raises a flag; the measuring
//! loops check it after every frame ([`check`]) and stop with [`Error::Interrupted`] (exit 130,
//! nothing written), the viewer quits at its next frame as if Esc had been pressed.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;

use crate::error::{Error, Result};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Install the handler (once per process; later calls do nothing). A failure to install it
/// leaves Ctrl-C with its default effect, which is logged, not fatal.
pub fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        if let Err(e) = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst)) {
            log::warn!("Ctrl-C handler: {e}");
        }
    });
}

/// Whether Ctrl-C was pressed since the handler was installed.
pub fn requested() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// `Err(Error::Interrupted)` once Ctrl-C was pressed.
pub fn check() -> Result<()> {
    if requested() {
        return Err(Error::Interrupted);
    }
    Ok(())
}
