//! The JSON documents of the measuring commands: the fields every one carries, and the
//! percentile summaries of their samples.

use serde_json::{json, Value};

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

/// Median, p5, p95, p99 and maximum of unsorted values (nearest rank), as the JSON documents
/// of `bench`, `overhead` and `timing` report them.
pub fn summary(values: &[f64]) -> Value {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    json!({
        "median": percentile(&sorted, 50.0),
        "p5": percentile(&sorted, 5.0),
        "p95": percentile(&sorted, 95.0),
        "p99": percentile(&sorted, 99.0),
        "max": sorted.last().copied().unwrap_or(0.0),
    })
}

/// A JSON document of `kind` (`bench`, `overhead`, `timing`): the fields every one carries —
/// schema version, device, driver, Mesa/LLVM string, resolution, build profile, git commit,
/// `LP_NUM_THREADS` — followed by `fields`.
pub fn document(device: &Device, kind: &str, resolution: (u32, u32), fields: Value) -> Value {
    let info = &device.info;
    let mut doc = json!({
        "schema_version": SCHEMA_VERSION,
        "kind": kind,
        "device": info.name,
        "driver": format!("{} {}", info.driver_name, info.driver_version),
        "driver_info": info.driver_info,
        "resolution": [resolution.0, resolution.1],
        "build_profile": if cfg!(debug_assertions) { "debug" } else { "release" },
        "git_commit": option_env!("MEADOW_GIT_COMMIT").unwrap_or("unknown"),
        "lp_num_threads": std::env::var("LP_NUM_THREADS").ok(),
    });
    if let (Some(out), Value::Object(more)) = (doc.as_object_mut(), fields) {
        out.extend(more);
    }
    doc
}

/// Per pass, the pipeline statistics of a frame (`{}` when the device has none).
pub fn statistics_json(passes: &[crate::render::PassTime]) -> Value {
    let map: serde_json::Map<String, Value> = passes
        .iter()
        .filter_map(|p| {
            let s = p.statistics?;
            let fields: serde_json::Map<String, Value> =
                s.fields().iter().map(|(name, value)| (name.to_string(), json!(value))).collect();
            Some((p.name.to_string(), Value::Object(fields)))
        })
        .collect();
    Value::Object(map)
}

/// What the cull kept and drew in a frame (`null` for brute force): the counts after each test
/// and the blades drawn per LOD bucket.
pub fn cull_json(counts: Option<&crate::render::culling::CullCounts>) -> Value {
    let Some(c) = counts else { return Value::Null };
    let buckets: Vec<Value> = c
        .segments
        .iter()
        .zip(c.drawn)
        .filter(|(s, _)| **s > 0)
        .map(|(s, d)| serde_json::json!({ "segments": s, "drawn": d }))
        .collect();
    serde_json::json!({
        "considered": c.considered,
        "tiles": c.tiles,
        "tiles_visible": c.tiles_visible,
        "after_tiles": c.after_tiles,
        "after_density": c.after_density,
        "after_frustum": c.after_frustum,
        "after_orientation": c.after_orientation,
        "after_occlusion": c.after_occlusion,
        "drawn": c.total_drawn(),
        "triangles": c.triangles(),
        "buckets": buckets,
    })
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
