//! The JSON documents of the measuring commands: the fields every one carries ([`Header`]), the
//! percentile summaries of their samples ([`Summary`]), the per-pass pipeline statistics and
//! cull counts they share, and the rule for rows a device could not measure ([`Outcome`]).
//! Every document is a `serde`-derived type, written and read through the same type: a field
//! is named once, in its struct, and a document missing one is refused naming it.

use std::collections::BTreeMap;

use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer, Serialize};

use crate::vk::Device;

/// Version of the JSON layout (of every document: `bench`, `overhead`, `timing`).
pub const SCHEMA_VERSION: u32 = 1;

/// Percentile by nearest rank of sorted values.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil().max(1.0) as usize;
    sorted[rank.min(sorted.len()) - 1]
}

/// Median, p5, p95, p99 and maximum of a sample (nearest rank), as every document reports them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The median.
    pub median: f64,
    /// The 5th percentile.
    pub p5: f64,
    /// The 95th percentile.
    pub p95: f64,
    /// The 99th percentile.
    pub p99: f64,
    /// The largest value; absent from the first v1 documents (docs/bench-thesis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
}

impl Summary {
    /// The summary of unsorted `values`.
    pub fn of(values: &[f64]) -> Self {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        Self {
            median: percentile(&sorted, 50.0),
            p5: percentile(&sorted, 5.0),
            p95: percentile(&sorted, 95.0),
            p99: percentile(&sorted, 99.0),
            max: Some(sorted.last().copied().unwrap_or(0.0)),
        }
    }
}

/// The fields every document carries first: schema version, kind, device, driver, Mesa/LLVM
/// string, resolution, build profile, git commit, `LP_NUM_THREADS`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// [`SCHEMA_VERSION`] when written.
    pub schema_version: u32,
    /// `bench`, `lod`, `msaa`, `animations`, `overhead` or `timing`.
    pub kind: String,
    /// The device's name.
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// The driver's own string (Mesa and LLVM versions on lavapipe).
    pub driver_info: String,
    /// Picture size.
    pub resolution: [u32; 2],
    /// `debug` or `release`.
    pub build_profile: String,
    /// The commit the binary was built from.
    pub git_commit: String,
    /// `LP_NUM_THREADS`, when set.
    pub lp_num_threads: Option<String>,
}

impl Header {
    /// The header of a document of `kind` measured on `device` at `resolution`, now.
    pub fn new(device: &Device, kind: &str, resolution: (u32, u32)) -> Self {
        let info = &device.info;
        Self {
            schema_version: SCHEMA_VERSION,
            kind: kind.into(),
            device: info.name.clone(),
            driver: format!("{} {}", info.driver_name, info.driver_version),
            driver_info: info.driver_info.clone(),
            resolution: [resolution.0, resolution.1],
            build_profile: if cfg!(debug_assertions) { "debug" } else { "release" }.into(),
            git_commit: option_env!("MEADOW_GIT_COMMIT").unwrap_or("unknown").into(),
            lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
        }
    }
}

/// What one pipeline-statistics query of a pass counted (`vk::query::PipelineStatistics`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Statistics {
    /// Vertices the input assembler fetched.
    pub input_vertices: u64,
    /// Primitives the input assembler formed.
    pub input_primitives: u64,
    /// Vertex shader invocations.
    pub vertex_invocations: u64,
    /// Primitives that reached the clipping stage.
    pub clipping_invocations: u64,
    /// Primitives that left it (what was rasterised).
    pub clipping_primitives: u64,
    /// Fragment shader invocations.
    pub fragment_invocations: u64,
}

/// Per pass name, its pipeline statistics.
pub type PassStatistics = BTreeMap<String, Statistics>;

/// Per pass, the pipeline statistics of a frame (empty when the device has none).
pub fn statistics(passes: &[crate::render::PassTime]) -> PassStatistics {
    passes
        .iter()
        .filter_map(|p| {
            let s = p.statistics?;
            let statistics = Statistics {
                input_vertices: s.input_vertices,
                input_primitives: s.input_primitives,
                vertex_invocations: s.vertex_invocations,
                clipping_invocations: s.clipping_invocations,
                clipping_primitives: s.clipping_primitives,
                fragment_invocations: s.fragment_invocations,
            };
            Some((p.name.to_string(), statistics))
        })
        .collect()
}

/// Per pass name, its GPU time in a frame (ms).
pub fn pass_times(passes: &[crate::render::PassTime]) -> BTreeMap<String, f64> {
    passes.iter().map(|p| (p.name.to_string(), p.ms)).collect()
}

/// A row a device measured (`T`), or one it could not, with the reason (`{"unsupported": …}`),
/// next to the fields that name the row.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Outcome<T> {
    /// Measured.
    Measured(T),
    /// Not run: why.
    Unsupported {
        /// Why the device cannot run it.
        unsupported: String,
    },
}

impl<T> Outcome<T> {
    /// What was measured, if it was.
    pub fn measured(&self) -> Option<&T> {
        match self {
            Outcome::Measured(t) => Some(t),
            Outcome::Unsupported { .. } => None,
        }
    }
}

/// An entry with `unsupported` is unsupported; any other is measured and must have every field
/// of `T` (a missing one is named, never read as absent).
impl<'de, T: DeserializeOwned> Deserialize<'de> for Outcome<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut fields = serde_json::Map::deserialize(deserializer)?;
        match fields.remove("unsupported") {
            Some(serde_json::Value::String(why)) => Ok(Outcome::Unsupported { unsupported: why }),
            Some(other) => Err(D::Error::custom(format!("unsupported: expected a string, found {other}"))),
            None => serde_json::from_value(serde_json::Value::Object(fields))
                .map(Outcome::Measured)
                .map_err(D::Error::custom),
        }
    }
}

/// What the cull kept and drew in a frame (`timing.json`'s `cull`): the counts after each test
/// and the blades drawn per LOD bucket.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CullSummary {
    /// Blades of every tile.
    pub considered: u32,
    /// Tiles.
    pub tiles: u32,
    /// Tiles that passed the tile tests.
    pub tiles_visible: u32,
    /// Blades of those tiles.
    pub after_tiles: u32,
    /// … then kept by the density LOD.
    pub after_density: u32,
    /// … then inside the frustum.
    pub after_frustum: u32,
    /// … then not seen edge-on.
    pub after_orientation: u32,
    /// … then not behind the terrain.
    pub after_occlusion: u32,
    /// Entries drawn: the blades and every further draw class's.
    pub drawn: u64,
    /// Blade triangles drawn.
    pub triangles: u64,
    /// Blades drawn per bucket that has segments.
    pub buckets: Vec<Bucket>,
    /// Per draw class (`render::draw_class`), the blades first: what it drew (absent from
    /// documents written before the cull had classes).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub classes: Vec<ClassDrawn>,
    /// What the visible list's capacity did to the kept blades (absent from documents written
    /// before the cull reported it).
    #[serde(flatten, default, skip_serializing_if = "Option::is_none")]
    pub thinning: Option<Thinning>,
}

/// What a draw class drew in a frame.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClassDrawn {
    /// The class (`blades`, or a further class's name).
    pub class: String,
    /// Entries of its buckets drawn.
    pub drawn: u64,
}

impl ClassDrawn {
    /// Per class of `c`, the blades first, what it drew.
    pub fn of(c: &crate::render::culling::CullCounts) -> Vec<Self> {
        let blades = Self { class: "blades".into(), drawn: c.blades_drawn() };
        let further = c.classes.iter().filter(|k| !k.name.is_empty());
        std::iter::once(blades)
            .chain(further.map(|k| Self { class: k.name.into(), drawn: u64::from(k.drawn) }))
            .collect()
    }
}

/// One LOD bucket of a frame: its segments and the blades it drew.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bucket {
    /// Segments of its blades.
    pub segments: u32,
    /// Blades drawn.
    pub drawn: u32,
}

impl CullSummary {
    /// The summary of `c`.
    pub fn of(c: &crate::render::culling::CullCounts) -> Self {
        let buckets = c
            .segments
            .iter()
            .zip(c.drawn)
            .filter(|(s, _)| **s > 0)
            .map(|(&segments, drawn)| Bucket { segments, drawn })
            .collect();
        Self {
            considered: c.considered,
            tiles: c.tiles,
            tiles_visible: c.tiles_visible,
            after_tiles: c.after_tiles,
            after_density: c.after_density,
            after_frustum: c.after_frustum,
            after_orientation: c.after_orientation,
            after_occlusion: c.after_occlusion,
            drawn: c.total_drawn(),
            triangles: c.triangles(),
            buckets,
            classes: ClassDrawn::of(c),
            thinning: Some(Thinning::of(c)),
        }
    }
}

/// What the visible list's capacity did to a frame's kept blades (`CullCounts`): the same three
/// fields in `timing.json`'s cull summary and `lod.json`'s counts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Thinning {
    /// Blades the blade tests kept, before the visible list's capacity thinned them to the
    /// blades drawn.
    pub wanted: u32,
    /// The capacity scale every bucket was thinned by: 1 when the list held every kept blade
    /// (`CullCounts::capacity_scale`).
    pub capacity_scale: f64,
    /// A block field's candidates without room for their verdicts, neither tested nor drawn.
    pub no_room: u32,
}

impl Thinning {
    /// The thinning `c` reports.
    pub fn of(c: &crate::render::culling::CullCounts) -> Self {
        Self { wanted: c.wanted, capacity_scale: c.capacity_scale(), no_room: c.no_room }
    }
}

/// A document as pretty JSON (every document type serialises: no map with non-string keys).
pub fn to_json<T: Serialize>(doc: &T) -> String {
    serde_json::to_string_pretty(doc).expect("a document serialises")
}

/// A number as the documents write it (`2.0`, `0.15`, `1e-7`): what the CSV files show.
pub fn number(x: f64) -> String {
    serde_json::Value::from(x).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 50.0), 50.0);
        assert_eq!(percentile(&v, 5.0), 5.0);
        assert_eq!(percentile(&v, 99.0), 99.0);
        assert_eq!(percentile(&[3.0], 95.0), 3.0);
    }
}
