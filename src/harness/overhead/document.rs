//! `overhead.json`, typed: what `meadow overhead` writes and its reports read.

use serde::{Deserialize, Serialize};

use crate::harness::document::{Header, Outcome};

/// An `overhead.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverheadDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// The CPU's hardware threads.
    pub worker_threads: usize,
    /// Blades of the scene.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Frames per strategy discarded first.
    pub warmup: u32,
    /// Frames per strategy measured.
    pub frames_per_strategy: u32,
    /// One per (clusters, strategy), the unsupported ones with the reason.
    pub rows: Vec<OverheadRow>,
}

/// A (clusters, strategy) row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverheadRow {
    /// Cluster count.
    pub clusters: u32,
    /// The submission strategy.
    pub strategy: String,
    /// What it measured, or why the device cannot run it.
    #[serde(flatten)]
    pub outcome: Outcome<StrategyMeasured>,
}

/// What a strategy measured at a cluster count (medians over its frames).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StrategyMeasured {
    /// Draw calls recorded.
    pub draw_calls_recorded: u32,
    /// Draws the GPU executes.
    pub draws_executed: u32,
    /// CPU recording (µs).
    pub cpu_record_us: f64,
    /// CPU submission (µs).
    pub cpu_submit_us: f64,
    /// 95th percentile of the recording (µs).
    pub cpu_record_us_p95: f64,
    /// Recording per draw executed (ns).
    pub ns_per_draw: f64,
    /// Draws executed per second of record + submit.
    pub draws_per_second: f64,
    /// GPU time of the passes.
    pub gpu_ms: f64,
    /// GPU time of the read-back copy (absent from documents recorded before it was apart).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub readback_ms: Option<f64>,
    /// Every measured frame.
    pub frames: Vec<OverheadFrame>,
}

/// One measured frame of a strategy.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OverheadFrame {
    /// CPU recording (µs).
    pub cpu_record_us: f64,
    /// CPU submission (µs).
    pub cpu_submit_us: f64,
    /// GPU time of the passes.
    pub gpu_ms: f64,
    /// GPU time of the read-back copy (absent as in [`StrategyMeasured::readback_ms`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub readback_ms: Option<f64>,
}
