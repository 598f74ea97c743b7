//! `msaa.json`, typed: what `meadow bench --preset msaa` writes and its reports read.

use serde::{Deserialize, Serialize};

use crate::harness::document::{Header, Summary};

/// A `msaa.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MsaaDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// The options of the run.
    pub options: MsaaOptionsRecord,
    /// The rows, in order.
    pub rows: Vec<MsaaRow>,
}

/// The options as the document records them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MsaaOptionsRecord {
    /// Blades of the stored field.
    pub blades: u32,
    /// Segments of the blades.
    pub segments: u32,
    /// Picture size.
    pub size: [u32; 2],
    /// Frames per variant discarded before the cost.
    pub warmup: u32,
    /// Frames per variant measured for the cost.
    pub frames: u32,
    /// Frames per variant of the pan.
    pub pan_frames: u32,
    /// Degrees the pan turns each frame.
    pub pan_deg_per_frame: f64,
    /// Simulation time of every frame (s).
    pub simulation_time_s: f64,
    /// Side of the blocks frames are compared in.
    pub diff_block: u32,
    /// The multisampled variants' sample count.
    pub samples: u32,
}

/// A row: how its blades are drawn, and its variants.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MsaaRow {
    /// Its name.
    pub label: String,
    /// Through the cull (outline as geometry) or brute force (alpha-tested).
    pub culled: bool,
    /// Blades of the scene.
    pub blades: usize,
    /// No MSAA, alpha to coverage, alpha test.
    pub variants: Vec<MsaaVariant>,
}

/// A variant of a row: its cost and its temporal stability.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MsaaVariant {
    /// Its name.
    pub variant: String,
    /// Samples per pixel.
    pub samples: u32,
    /// Whether alpha to coverage is on.
    pub alpha_to_coverage: bool,
    /// GPU time of the cost frames.
    pub gpu_ms: Summary,
    /// Every cost frame's GPU time.
    pub frames_ms: Vec<f64>,
    /// Median over no MSAA's.
    pub cost_ratio: f64,
    /// Mean frame-to-frame change of the pan (%).
    pub change_percent: f64,
    /// Every frame-to-frame change of the pan (%).
    pub changes_percent: Vec<f64>,
    /// Mean change over no MSAA's.
    pub change_ratio: f64,
}
