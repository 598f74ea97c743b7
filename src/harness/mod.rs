//! The measuring harness built on the renderer: `meadow bench`, `meadow overhead` and
//! `meadow timing`, and their PNG charts.

pub mod bench;
pub mod overhead;
pub mod plot;
pub mod timing;
