//! `timing.json`, typed: what `meadow timing` writes and its report reads.

use serde::{Deserialize, Serialize};

use crate::harness::document::{CullSummary, Header, PassStatistics, Summary};

/// A `timing.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimingDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Blades asked for.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Animation mode (or `floor`).
    pub mode: String,
    /// Frames discarded at the start of each run.
    pub warmup: u32,
    /// Frames measured per run.
    pub frames_per_run: u32,
    /// The fixed time step between frames in seconds (`--dt`; absent from older v1 documents,
    /// which used 1/60 s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt_s: Option<f64>,
    /// `--fly`: the camera's speed along its heading (m/s; absent when it stood still).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fly_m_per_s: Option<f32>,
    /// How the blades were submitted (absent from older v1 documents).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub submission: Option<SubmissionSummary>,
    /// Blades per instance of the blade draws (absent from older v1 documents).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blades_per_instance: Option<u32>,
    /// The device's timestamp period.
    pub timestamp_period_ns: f64,
    /// Valid bits of the queue's timestamps.
    pub timestamp_valid_bits: u32,
    /// Whether the clocks were calibrated (`VK_EXT_calibrated_timestamps`).
    pub calibrated_timestamps: bool,
    /// GPU frame time, 1 frame in flight.
    pub gpu_frame_ms: Summary,
    /// CPU recording, 1 frame in flight.
    pub cpu_record_ms: Summary,
    /// CPU submission, 1 frame in flight.
    pub cpu_submit_ms: Summary,
    /// Per pass, its GPU time, 1 frame in flight.
    pub passes: Vec<PassSummary>,
    /// The last frame's pipeline statistics (`null` without frames).
    pub pipeline_statistics: Option<PassStatistics>,
    /// What the cull kept in the last frame (`null` by brute force; absent from older v1
    /// documents).
    #[serde(default)]
    pub cull: Option<CullSummary>,
    /// Per number of frames in flight, its run.
    pub frames_in_flight: Vec<RunSummary>,
}

/// The submission strategy the frames were drawn with (`--submission`), and the clusters it
/// split the blades into (`--clusters`; 1 for the strategies of one draw).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubmissionSummary {
    /// The strategy's name.
    pub strategy: String,
    /// Clusters.
    pub clusters: u32,
}

/// One pass's GPU time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassSummary {
    /// Its name.
    pub pass: String,
    /// Its GPU time.
    pub gpu_ms: Summary,
}

/// A run with a number of frames in flight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Frames in flight.
    pub frames_in_flight: usize,
    /// Frames measured.
    pub frames: usize,
    /// Frames per second of the measured span.
    pub fps: f64,
    /// Wall time of the run (s).
    pub wall_s: f64,
    /// GPU frame spans over the measured span.
    pub gpu_busy_fraction: f64,
    /// CPU record + submit per frame.
    pub cpu_work_ms_per_frame: f64,
    /// Share of the recording during which the GPU rendered an earlier frame.
    pub cpu_gpu_overlap_fraction: f64,
    /// CPU time blocked on fences.
    pub cpu_wait_ms: Summary,
    /// Between consecutive GPU frame ends.
    pub frame_interval_ms: Summary,
    /// How GPU time was mapped to CPU time.
    pub clock: ClockRecord,
}

/// The mapping of the two clocks in the document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClockRecord {
    /// `calibrated` or `estimated`.
    pub method: String,
    /// Its uncertainty (ns).
    pub deviation_ns: f64,
}
