//! The measuring harness built on the renderer: `meadow bench` ([`bench`]), `meadow overhead`
//! ([`overhead`]) and `meadow timing` ([`timing`]) run the renderer under controlled conditions
//! and write versioned JSON documents ([`document`]), CSV, tables and PNG charts ([`plot`]).
//!
//! A tool, not part of the renderer library: it imports [`crate::render`] and [`crate::vk`], never
//! the other way round.

pub mod bench;
pub mod document;
pub mod overhead;
pub mod plot;
pub mod timing;
