//! `lod.json`, typed: what `meadow bench --preset lod` writes and its reports read
//! (`docs/lod.schema.json` describes the same fields).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::harness::document::{Header, Summary};

/// A `lod.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LodDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// The options of the run.
    pub options: LodOptionsRecord,
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames_per_variant: u32,
    /// The rows, in order.
    pub rows: Vec<LodMeasuredRow>,
}

/// The options as the document records them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LodOptionsRecord {
    /// How many rows.
    pub rows: usize,
    /// Picture size.
    pub size: [u32; 2],
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// Segments of brute force and of the nearest LOD bucket.
    pub segments: u32,
    /// Simulation time of every frame (s).
    pub simulation_time_s: f64,
    /// Side of the blocks the pictures are compared in.
    pub diff_block: u32,
}

/// The field of a row, by `kind`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum FieldRecord {
    /// Every blade stored.
    Stored {
        /// Blades.
        blades: u32,
        /// Seed.
        seed: u64,
    },
    /// Camera-following blocks, measured against a stored reference.
    Blocks {
        /// `infinite`.
        size: String,
        /// Blades per square metre.
        density: f64,
        /// Seed.
        seed: u64,
        /// What brute force renders instead.
        reference: Reference,
    },
}

/// The stored field an unbounded field is measured against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// `stored`.
    pub kind: String,
    /// Its blades.
    pub blades: u32,
    /// Its view (`default`).
    pub view: String,
}

/// Where a row's camera stood.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraRecord {
    /// Position (m).
    pub position: [f64; 3],
    /// Yaw (degrees).
    pub yaw_deg: f64,
    /// Pitch (degrees).
    pub pitch_deg: f64,
}

/// The box-filtered difference of the GPU-driven picture to brute force's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DiffRecord {
    /// Side of the blocks (px).
    pub block: u32,
    /// Mean over the blocks, % of full scale.
    pub mean_percent: f64,
    /// 99th-percentile block.
    pub p99_percent: f64,
    /// Largest block.
    pub max_percent: f64,
}

/// One row of the document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LodMeasuredRow {
    /// Its name.
    pub label: String,
    /// Its field.
    pub field: FieldRecord,
    /// Blades of the field.
    pub blades: u32,
    /// Segments.
    pub segments: u32,
    /// The view's name.
    pub view: String,
    /// The GPU-driven camera.
    pub camera: CameraRecord,
    /// Brute force's median over the GPU-driven one's.
    pub ratio: f64,
    /// The cull passes' share of the GPU-driven frame (median).
    pub cull_share: f64,
    /// `null` for a row of two scenes (pictures of different scenes are not compared).
    pub diff: Option<DiffRecord>,
    /// Brute force, then GPU-driven.
    pub variants: Vec<LodVariant>,
}

impl LodMeasuredRow {
    /// Variant `name`.
    pub fn variant(&self, name: &str) -> Option<&LodVariant> {
        self.variants.iter().find(|v| v.variant == name)
    }
}

/// A variant of a row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LodVariant {
    /// `brute-force` or `gpu-driven`.
    pub variant: String,
    /// Its frame times.
    pub gpu_ms: Summary,
    /// Its cull passes' times.
    pub cull_ms: Summary,
    /// The median over the frames of each frame's cull passes / its GPU time.
    pub cull_share: f64,
    /// Blades drawn.
    pub drawn_blades: u64,
    /// Blade triangles drawn.
    pub blade_triangles: u64,
    /// What the cull kept (`null` for brute force).
    pub counts: Option<CountsRecord>,
    /// Its measured frames.
    pub frames: Vec<LodFrame>,
}

/// What the cull kept after each test and drew per bucket.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CountsRecord {
    /// Blades of every tile.
    pub considered: u32,
    /// … of the tiles that passed the tile tests.
    pub after_tiles: u32,
    /// … then kept by the density LOD.
    pub after_density: u32,
    /// … then inside the frustum.
    pub after_frustum: u32,
    /// … then not seen edge-on.
    pub after_orientation: u32,
    /// … then not behind the terrain.
    pub after_occlusion: u32,
    /// Tiles that passed the tile tests.
    pub tiles_visible: u32,
    /// Tiles.
    pub tiles: u32,
    /// Blades drawn per bucket.
    pub drawn: Vec<u32>,
    /// Segments of each bucket.
    pub bucket_segments: Vec<u32>,
    /// Entries drawn: the blades and every further draw class's.
    pub total_drawn: u64,
    /// Blade triangles drawn.
    pub triangles: u64,
    /// Per draw class, the blades first: what it drew (absent from documents written before the
    /// cull had classes).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub classes: Vec<crate::harness::document::ClassDrawn>,
    /// What the visible list's capacity did to the kept blades (absent from documents written
    /// before the cull reported it).
    #[serde(flatten, default, skip_serializing_if = "Option::is_none")]
    pub thinning: Option<crate::harness::document::Thinning>,
}

/// One measured frame of a variant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LodFrame {
    /// GPU time.
    pub gpu_ms: f64,
    /// The passes whose name starts with `cull`.
    pub cull_ms: f64,
    /// Per pass, its GPU time.
    pub passes_ms: BTreeMap<String, f64>,
}
