//! `animations.json`, typed: what `meadow bench --preset animations` writes and its reports read.

use serde::{Deserialize, Serialize};

use crate::harness::document::{Header, Summary};

/// An `animations.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnimationsDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// The options of the run.
    pub options: AnimationsOptionsRecord,
    /// The rows, in order.
    pub rows: Vec<AnimationsRow>,
}

/// The options as the document records them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnimationsOptionsRecord {
    /// The responses compared, static first (every ratio's reference).
    pub animations: Vec<String>,
    /// Picture size.
    pub size: [u32; 2],
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// The fixed step, seconds: frame k is at k steps, one step a frame.
    pub dt_s: f64,
}

/// A row: a scene and how it is drawn, and one variant per response.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnimationsRow {
    /// Its name.
    pub label: String,
    /// Through the cull (and LOD) or brute force.
    pub culled: bool,
    /// Blades stored (a block field's: one block's).
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// The wind field of the row: analytic, or the other field its variants are also measured
    /// under (each variant names its own).
    pub wind_field: String,
    /// The variants, static first.
    pub variants: Vec<AnimationsVariant>,
}

/// A response in a row: its frame time, its ratio to static, and its own passes' time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnimationsVariant {
    /// The response (`--animation`'s value).
    pub animation: String,
    /// The response's name in reports (`BladeResponse::name`).
    pub response: String,
    /// The wind field it reads (`WindField::name`).
    #[serde(default)]
    pub wind_field: String,
    /// GPU time of the measured frames.
    pub gpu_ms: Summary,
    /// Every measured frame's GPU time.
    pub frames_ms: Vec<f64>,
    /// Median GPU time over static's.
    pub ratio_to_static: f64,
    /// The names of the response's own passes.
    pub passes: Vec<String>,
    /// GPU time of those passes, per measured frame.
    pub response_ms: Summary,
    /// Steps taken each frame.
    pub steps_per_frame: u32,
    /// The response's passes' median time over its steps a frame: what one step costs.
    pub ms_per_step: f64,
}
