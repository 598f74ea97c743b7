//! SIGINT (Ctrl-C), SIGTERM and SIGHUP, in every command: the handler only records the signal;
//! the measuring loops and `render` check it after every frame ([`check`]), and stop with
//! [`Error::Interrupted`] (exit 128 + the signal's number, as a shell reports it); the viewer
//! quits at its next frame without its exit screenshot. No file is published once a signal came
//! (`output::write_atomically` and `output::write_set` check it before renaming), so a stopped
//! command leaves neither a temporary nor a half set nor an empty output folder. A second signal
//! before the command stopped ends it at once (the default effect), as a user pressing Ctrl-C
//! twice expects.

use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Once;

use crate::error::{Error, Result};

/// The signals that stop a command.
const SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// The first signal received (0: none).
static RECEIVED: AtomicI32 = AtomicI32::new(0);

/// The handler: an atomic store, which is async-signal-safe. A second signal, while the command
/// has not stopped yet (a long step between two checks), takes the signal's default effect at
/// once: `signal` and `raise` are async-signal-safe too.
extern "C" fn record(signal: libc::c_int) {
    if RECEIVED.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst).is_err() {
        // SAFETY: restoring the default disposition and raising are async-signal-safe.
        unsafe {
            libc::signal(signal, libc::SIG_DFL);
            libc::raise(signal);
        }
    }
}

/// Install the handler for [`SIGNALS`] (once per process; later calls do nothing). A failure to
/// install it leaves that signal with its default effect, which is logged, not fatal.
pub fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        for signal in SIGNALS {
            // SAFETY: a zeroed sigaction with an empty mask is valid; the handler only stores to
            // an atomic. SA_RESTART: system calls the signal interrupts are restarted, so no
            // read or write of the command sees EINTR.
            let installed = unsafe {
                let mut action: libc::sigaction = std::mem::zeroed();
                action.sa_sigaction = record as extern "C" fn(libc::c_int) as libc::sighandler_t;
                action.sa_flags = libc::SA_RESTART;
                libc::sigemptyset(&mut action.sa_mask);
                libc::sigaction(signal, &action, std::ptr::null_mut())
            };
            if installed != 0 {
                log::warn!("signal {signal} handler: {}", std::io::Error::last_os_error());
            }
        }
    });
}

/// The signal received since the handler was installed, if any.
pub fn received() -> Option<i32> {
    Some(RECEIVED.load(Ordering::SeqCst)).filter(|&s| s != 0)
}

/// Whether a signal came since the handler was installed.
pub fn requested() -> bool {
    received().is_some()
}

/// `Err(Error::Interrupted)` once a signal came.
pub fn check() -> Result<()> {
    match received() {
        Some(signal) => Err(Error::Interrupted { signal }),
        None => Ok(()),
    }
}
