//! The measuring harness built on the renderer: `meadow bench` ([`bench`](mod@bench)), `meadow overhead`
//! ([`overhead`]) and `meadow timing` ([`timing`]) run the renderer under controlled conditions
//! through one measuring loop ([`measure`]) and write versioned JSON documents, each a
//! `serde`-derived type ([`document`] and each command's own), CSV, tables and PNG charts ([`plot`]).
//!
//! A tool, not part of the renderer library: it imports [`crate::render`] and [`crate::vk`], never
//! the other way round.

pub mod bench;
pub mod document;
pub(crate) mod measure;
pub mod overhead;
pub mod plot;
pub mod timing;
pub mod trace;

/// Frames counted towards a measuring command's progress report (`progress(done, total)`).
pub(crate) struct Progress<'a> {
    done: u64,
    total: u64,
    report: &'a mut dyn FnMut(u64, u64),
}

impl<'a> Progress<'a> {
    /// `total` frames to go, none done.
    pub(crate) fn new(total: u64, report: &'a mut dyn FnMut(u64, u64)) -> Self {
        Self { done: 0, total, report }
    }

    /// One frame rendered: counted and reported; `Err(Error::Interrupted)` once a signal came
    /// (Ctrl-C, SIGTERM, SIGHUP: the command then stops at this frame and writes nothing).
    pub(crate) fn rendered(&mut self) -> crate::error::Result<()> {
        self.done += 1;
        (self.report)(self.done, self.total);
        crate::app::interrupt::check()
    }

    /// `n` frames that will not be rendered (an unsupported variant): counted, and reported with
    /// the next rendered frame.
    pub(crate) fn skipped(&mut self, n: u64) {
        self.done += n;
    }
}
