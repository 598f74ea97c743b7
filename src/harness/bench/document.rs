//! `bench.json`, typed: what `meadow bench` writes and what `--compare` and the reports read
//! back, through the same structs (`docs/bench.schema.json` describes the same fields).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::harness::document::{Header, Outcome, PassStatistics, Summary};

/// A `bench.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames_per_variant: u32,
    /// The fixed time step between a variant's frames, in seconds (frame n is drawn at n · dt;
    /// absent from older v1 documents, which used 1/60 s too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt_s: Option<f64>,
    /// Memory of a row's offscreen target.
    pub memory_per_row_bytes: u64,
    /// The (blades, segments) rows.
    pub rows: Vec<BenchRow>,
}

/// One (blades, segments) row of the table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchRow {
    /// Blades.
    pub blades: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Blade triangles a frame draws.
    pub triangles: u64,
    /// Every variant, the unsupported ones with the reason.
    pub variants: Vec<BenchVariant>,
}

impl BenchRow {
    /// Variant `name`'s measurement, when it was measured.
    pub fn variant(&self, name: &str) -> Option<&VariantMeasured> {
        self.variants.iter().find(|v| v.variant == name)?.outcome.measured()
    }
}

/// A variant of a row: its name (`static`, `texture/blade`, `floor`…) and what it measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchVariant {
    /// Its name.
    pub variant: String,
    /// Its measurement, or why the device could not run it.
    #[serde(flatten)]
    pub outcome: Outcome<VariantMeasured>,
}

/// What a variant measured: summaries of its frames, and the frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantMeasured {
    /// GPU time of the passes.
    pub gpu_ms: Summary,
    /// The copy of the picture to the host after the passes: not in `gpu_ms`. Absent from
    /// documents recorded before meadow reported the copy apart (docs/bench-thesis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub readback_ms: Option<Summary>,
    /// CPU record + submit of a frame.
    pub cpu_record_submit_ms: Summary,
    /// CPU time blocked on the frame fence.
    pub cpu_wait_ms: Summary,
    /// The counts are the same every frame (fixed scene and camera): the last frame's.
    pub pipeline_statistics: PassStatistics,
    /// Every measured frame.
    pub frames: Vec<BenchFrame>,
}

/// One measured frame of a variant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchFrame {
    /// GPU time of the passes.
    pub gpu_ms: f64,
    /// GPU time of the read-back copy (absent as in [`VariantMeasured::readback_ms`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub readback_ms: Option<f64>,
    /// Per pass, its GPU time.
    pub passes_ms: BTreeMap<String, f64>,
    /// Per pass, its pipeline statistics.
    pub pipeline_statistics: PassStatistics,
    /// CPU time to record the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of the submission.
    pub cpu_submit_ms: f64,
    /// CPU time blocked on the frame fence.
    pub cpu_wait_ms: f64,
}

impl BenchFrame {
    /// The frame of `t`.
    pub fn of(t: &crate::render::FrameTimings) -> Self {
        Self {
            gpu_ms: t.gpu_ms,
            readback_ms: Some(t.readback_ms),
            passes_ms: crate::harness::document::pass_times(&t.passes),
            pipeline_statistics: crate::harness::document::statistics(&t.passes),
            cpu_record_ms: t.cpu_record_ms,
            cpu_submit_ms: t.cpu_submit_ms,
            cpu_wait_ms: t.cpu_wait_ms,
        }
    }
}

impl VariantMeasured {
    /// The summaries of `frames` (measured, in order), and the frames.
    pub fn of(frames: Vec<BenchFrame>) -> Self {
        let field = |f: fn(&BenchFrame) -> f64| Summary::of(&frames.iter().map(f).collect::<Vec<f64>>());
        Self {
            gpu_ms: field(|f| f.gpu_ms),
            readback_ms: Some(field(|f| f.readback_ms.unwrap_or(0.0))),
            cpu_record_submit_ms: field(|f| f.cpu_record_ms + f.cpu_submit_ms),
            cpu_wait_ms: field(|f| f.cpu_wait_ms),
            pipeline_statistics: frames.last().map(|f| f.pipeline_statistics.clone()).unwrap_or_default(),
            frames,
        }
    }
}

/// Documents for the harness's unit tests: a header, and rows of measured variants whose
/// frames have the given GPU times (0.05 ms to record and to submit each).
#[cfg(test)]
pub(crate) mod fixtures {
    use super::*;

    /// A header of a run on device `d`.
    pub(crate) fn header() -> Header {
        Header {
            schema_version: crate::harness::document::SCHEMA_VERSION,
            kind: "bench".into(),
            device: "d".into(),
            driver: "v".into(),
            driver_info: "i".into(),
            resolution: [8, 8],
            build_profile: "release".into(),
            git_commit: "unknown".into(),
            lp_num_threads: None,
        }
    }

    /// A measured variant of frames of `gpu_ms`.
    pub(crate) fn variant(name: &str, gpu_ms: &[f64]) -> BenchVariant {
        let frame = |&gpu_ms: &f64| BenchFrame {
            gpu_ms,
            readback_ms: Some(0.0),
            passes_ms: BTreeMap::new(),
            pipeline_statistics: BTreeMap::new(),
            cpu_record_ms: 0.05,
            cpu_submit_ms: 0.05,
            cpu_wait_ms: 0.0,
        };
        let measured = VariantMeasured::of(gpu_ms.iter().map(frame).collect());
        BenchVariant { variant: name.into(), outcome: Outcome::Measured(measured) }
    }

    /// A row at 4 segments of `variants` (name, frame times).
    pub(crate) fn row(blades: u32, variants: &[(&str, &[f64])]) -> BenchRow {
        let variants = variants.iter().map(|(name, ms)| variant(name, ms)).collect();
        BenchRow { blades, segments: 4, triangles: 8, variants }
    }

    /// A document of `rows`.
    pub(crate) fn doc(rows: Vec<BenchRow>) -> BenchDocument {
        BenchDocument { header: header(), warmup: 0, frames_per_variant: 1, dt_s: None, memory_per_row_bytes: 0, rows }
    }
}
