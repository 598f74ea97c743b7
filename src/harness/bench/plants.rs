//! `meadow bench --preset plants`: issue #36's numbers side by side in one run (`pairs`). Eight
//! renderers render in turn, in four pairs, from each scene's default camera, animated as the
//! CLI's default (keyframes posed once per drawn blade):
//!
//! - **flowers on the default block field** (unbounded, 400 blades/m², the gentle relief):
//!   `FLOWERS_PER_M2` flowers against none. Target: ≤ 1.15×.
//! - **flowers on the default stored field** (100 000 blades): the same. Target: ≤ 1.15×.
//! - **clumps on the block field** and **on the stored field**: `CLUMP_SIZE_M` clumps against
//!   none. Target: ≤ 1.03×.
//!
//! `plants.json` holds every variant's GPU times and what each class drew, and each pair's ratio
//! and picture difference; `table` prints them.

use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::bench::pairs::{self, Pair, PairBenchOptions, PairSpec};
use crate::harness::document::{to_json, Header};
use crate::harness::measure::Schedule;
use crate::render::animation::{AnimationSettings, Eval};
use crate::scene::clumps::Clumps;
use crate::scene::field::FieldSpec;
use crate::scene::flowers::Flowers;
use crate::scene::{Camera, Scene};
use crate::vk::Device;

/// The files of a run.
pub const FILES: [&str; 1] = ["plants.json"];
/// The flowers' density (per m²).
pub const FLOWERS_PER_M2: f32 = 20.0;
/// The clumps' size (m).
pub const CLUMP_SIZE_M: f32 = 1.5;
/// The stored field's blades.
pub const STORED_BLADES: u32 = 100_000;
/// The seed of the fields.
pub const SEED: u64 = 1;

/// A `plants.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlantsDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Rounds discarded, rounds measured.
    pub warmup: u32,
    pub frames: u32,
    /// The pairs, in order.
    pub pairs: Vec<Pair>,
}

/// The pairs' (label, reference name, subject name, target).
const PAIRS: [PairSpec; 4] = [
    ("flowers 20/m² / none, default block field", "block field", "block field, flowers", 1.15),
    ("flowers 20/m² / none, default stored field", "stored field", "stored field, flowers", 1.15),
    ("clumps 1.5 m / none, default block field", "block field", "block field, clumps", 1.03),
    ("clumps 1.5 m / none, default stored field", "stored field", "stored field, clumps", 1.03),
];

/// The eight scenes in `PAIRS`' order.
fn scenes() -> Result<Vec<Scene>> {
    let spec = FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 };
    let block = Scene::blocks(spec, SEED);
    let stored = Scene::generate(STORED_BLADES, SEED);
    let flowers = Flowers { per_m2: FLOWERS_PER_M2 };
    let clumps = Clumps { size_m: CLUMP_SIZE_M };
    Ok(vec![
        block.clone(),
        block.clone().with_flowers(flowers)?,
        stored.clone(),
        stored.clone().with_flowers(flowers)?,
        block.clone(),
        block.with_clumps(clumps),
        stored.clone(),
        stored.with_clumps(clumps),
    ])
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(device: &Arc<Device>, options: &PairBenchOptions, progress: impl FnMut(u64, u64)) -> Result<PlantsDocument> {
    let scenes = scenes()?;
    let cameras: Vec<Camera> = scenes.iter().map(Scene::default_camera).collect();
    let schedule = Schedule { warmup: options.warmup, frames: options.frames };
    // The CLI's default: keyframes posed once per drawn blade with the cull, which the flowers'
    // stems need (`--eval auto`).
    let animation = AnimationSettings { eval: Eval::default_for(true), ..AnimationSettings::default() };
    let animated = pairs::Animated::still(&animation);
    let pairs = pairs::run(device, (&PAIRS, &scenes, &cameras, animated), options.size, schedule, progress)?;
    Ok(PlantsDocument {
        header: Header::new(device, "plants", options.size),
        warmup: options.warmup,
        frames: options.frames,
        pairs,
    })
}

/// Write `plants.json` into `dir`.
pub fn write(doc: &PlantsDocument, dir: &Path) -> Result<()> {
    crate::app::write_text(&dir.join(FILES[0]), &to_json(doc))
}

/// The pairs as a text table.
pub fn table(doc: &PlantsDocument) -> String {
    let head = format!("plants, {} rounds after {} of warm-up\n", doc.frames, doc.warmup);
    head + &pairs::table_rows(&doc.pairs)
}
