//! `meadow bench --preset landscape`: issue #35's numbers side by side in one run. Six renderers
//! of an unbounded field render in turn (A B C D E F A B …, warm-up frames discarded), in three
//! pairs, each a reference and a subject whose frame is measured against it:
//!
//! - **the relief against its export**: the gentle relief, and the same relief exported as a
//!   16-bit heightmap (`Heightmap::from_relief`, 4 001 × 4 001 texels at 0.5 m over 2 km, what
//!   `examples/landscape_maps.rs relief` writes), from the default camera. Target: the map's frame
//!   at ≤ 1.1× the relief's, and the pictures within the goldens' tolerance (99.9 % of pixels
//!   within ±3, none over 32).
//! - **a split cover against a full one**, from the default camera and from `ABOVE_M` above:
//!   covering maps over 200 m of the relief, a full one (1 × 1 of 255) and one bare for x < 0
//!   (64 × 1: half the default view). Target: the split's frame at ≤ 0.65× the full one's.
//!
//! `landscape.json` holds every variant's GPU times and drawn blades and each pair's ratio and
//! picture difference; `table` prints them.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::bench::pairs::{self, Pair, PairBenchOptions, PairSpec};
use crate::harness::document::{to_json, Header};
use crate::harness::measure::Schedule;
use crate::scene::cover::{Cover, CoverMap, MapPlacement};
use crate::scene::field::{FieldSpec, Relief, ReliefKind};
use crate::scene::heightmap::Heightmap;
use crate::scene::{Camera, Scene};
use crate::vk::Device;

/// The files of a run.
pub const FILES: [&str; 1] = ["landscape.json"];
/// The exported relief's extent (m; its mirrored period divides the world's) and texel spacing.
pub const EXPORT_EXTENT_M: f64 = 2000.0;
/// The exported relief's texel spacing (m): the clipmap's vertices fall on its texels.
pub const EXPORT_SPACING_M: f64 = 0.5;
/// The cover maps' extent (m).
pub const COVER_EXTENT_M: f64 = 200.0;
/// The camera above: its height over the ground at the origin (m), looking straight down.
pub const ABOVE_M: f32 = 40.0;
/// The seed of the relief and the block.
pub const SEED: u64 = 1;

/// A `landscape.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LandscapeDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Rounds discarded, rounds measured.
    pub warmup: u32,
    pub frames: u32,
    /// The export: its texels a side and how long making it took (ms, CPU).
    pub export_texels: u32,
    pub export_ms: f64,
    /// The pairs, in order.
    pub pairs: Vec<Pair>,
}

/// The pairs' (label, reference name, subject name, target).
const PAIRS: [PairSpec; 3] = [
    ("exported heightmap / procedural relief, default camera", "relief", "exported map", 1.1),
    ("split cover / full cover, default camera", "full cover", "split cover", 0.65),
    ("split cover / full cover, from above", "full cover, above", "split cover, above", 0.65),
];

/// The six scenes in `PAIRS`' order, and how long the export took (ms).
fn scenes() -> ([Scene; 6], u32, f64) {
    let spec = FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 };
    let relief = Scene::blocks_on(spec, ReliefKind::Gentle, SEED);
    let started = Instant::now();
    let (map, _) =
        Heightmap::from_relief(&Relief::of_kind(ReliefKind::Gentle, SEED), EXPORT_EXTENT_M, EXPORT_SPACING_M);
    let export_ms = started.elapsed().as_secs_f64() * 1e3;
    let side = map.width;
    let exported = Scene::blocks_on_map(spec, Arc::new(map), SEED);
    let placement = MapPlacement { x: COVER_EXTENT_M, z: COVER_EXTENT_M, mirrored: true };
    let cover = |width, grass: Vec<u8>| {
        let flowers = vec![255; grass.len()];
        let map = CoverMap { width, height: 1, grass, flowers, placement };
        relief.clone().with_cover(Cover { slope_limit_deg: None, map: Some(Arc::new(map)) }, 0, SEED)
    };
    let full = cover(1, vec![255]);
    let split = cover(64, (0..64).map(|x| if x < 32 { 0 } else { 255 }).collect());
    ([relief.clone(), exported, full.clone(), split.clone(), full, split], side, export_ms)
}

/// Each variant's camera: the default one of its scene, or looking down from `ABOVE_M`.
fn cameras(scenes: &[Scene; 6]) -> Vec<Camera> {
    (0..6)
        .map(|i| match i {
            4 | 5 => {
                let ground = scenes[i].ground(0.0, 0.0);
                Camera { position: glam::Vec3::new(0.0, ground + ABOVE_M, 0.0), yaw_deg: 0.0, pitch_deg: -89.0 }
            }
            _ => scenes[i].default_camera(),
        })
        .collect()
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(
    device: &Arc<Device>,
    options: &PairBenchOptions,
    progress: impl FnMut(u64, u64),
) -> Result<LandscapeDocument> {
    let (scenes, export_texels, export_ms) = scenes();
    let cameras = cameras(&scenes);
    let schedule = Schedule { warmup: options.warmup, frames: options.frames };
    // The library's default animation, as this benchmark was first measured with.
    let animation = crate::render::animation::AnimationSettings::default();
    let animated = pairs::Animated::still(&animation);
    let pairs = pairs::run(device, (&PAIRS, &scenes, &cameras, animated), options.size, schedule, progress)?;
    Ok(LandscapeDocument {
        header: Header::new(device, "landscape", options.size),
        warmup: options.warmup,
        frames: options.frames,
        export_texels,
        export_ms,
        pairs,
    })
}

/// Write `landscape.json` into `dir`.
pub fn write(doc: &LandscapeDocument, dir: &Path) -> Result<()> {
    crate::app::write_text(&dir.join(FILES[0]), &to_json(doc))
}

/// The pairs as a text table.
pub fn table(doc: &LandscapeDocument) -> String {
    let head = format!(
        "landscape, {} rounds after {} of warm-up; the exported relief: {} x {} texels, made in {:.0} ms\n",
        doc.frames, doc.warmup, doc.export_texels, doc.export_texels, doc.export_ms
    );
    head + &pairs::table_rows(&doc.pairs)
}
