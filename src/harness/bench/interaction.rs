//! `meadow bench --preset interaction`: issue #34's cost side by side in one run (`pairs`). Four
//! renderers render in turn, in two pairs, from each scene's default camera, animated as the CLI's
//! default (keyframes posed once per drawn blade), the simulation time advancing one 1/60 s step a
//! round, the measured rounds from `START_S` and the warm-up's before them:
//!
//! - **the default stored field** (100 000 blades): `COLLIDERS` moving spheres against none;
//! - **the unbounded block field** (400 blades/m²): the same.
//!
//! The spheres are of `RADIUS_M`, resting on the ground, moving at `SPEED_M_S` along seeded
//! directions from seeded points within `REACH_M` of the camera. Push-out and the pressed map are on
//! (their trails from t = 0 swept into the map on the first frame), and so are the interaction
//! patches (at least `PATCH_WARMUP_ROUNDS` rounds of warm-up, so that as many blades hold a patch
//! as a walk keeps; the table reports how many, and their memory). Target: ≤ 1.25×.
//!
//! `interaction.json` holds every variant's GPU times and what each drew, and each pair's ratio and
//! picture difference; `table` prints them.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::bench::pairs::{self, Animated, Pair, PairBenchOptions, PairSpec};
use crate::harness::document::{to_json, Header};
use crate::harness::measure::Schedule;
use crate::render::animation::{AnimationSettings, Eval};
use crate::scene::field::FieldSpec;
use crate::scene::{Camera, Scene};
use crate::vk::Device;
use crate::wind::Collider;

/// The files of a run.
pub const FILES: [&str; 1] = ["interaction.json"];
/// The moving spheres of the subjects.
pub const COLLIDERS: usize = 64;
/// Their radius, speed and how far from the camera they start, in metres (and m/s).
pub const RADIUS_M: f32 = 0.3;
pub const SPEED_M_S: f32 = 1.5;
pub const REACH_M: f32 = 20.0;
/// The simulation time of the first measured round, in seconds: the spheres have left trails by
/// then.
pub const START_S: f32 = 2.2;
/// Warm-up rounds at least: 2.1 s of steps, past `patches::TIMEOUT_S + BLEND_S`.
pub const PATCH_WARMUP_ROUNDS: u32 = 126;
/// The stored field's blades and the fields' seed.
pub const STORED_BLADES: u32 = 100_000;
pub const SEED: u64 = 1;

/// An `interaction.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InteractionDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// Rounds discarded, rounds measured.
    pub warmup: u32,
    pub frames: u32,
    /// The spheres of the subjects: how many, their radius and speed.
    pub colliders: usize,
    pub radius_m: f32,
    pub speed_m_s: f32,
    /// The pairs, in order.
    pub pairs: Vec<Pair>,
}

/// The pairs' (label, reference name, subject name, target).
const PAIRS: [PairSpec; 2] = [
    ("64 moving colliders / none, default stored field", "stored field", "stored field, colliders", 1.25),
    ("64 moving colliders / none, unbounded block field", "block field", "block field, colliders", 1.25),
];

/// `COLLIDERS` spheres resting on `scene`'s ground, from seeded points within `REACH_M` of
/// `camera`, moving along seeded directions (a small linear congruential generator: the same
/// spheres on every machine).
pub fn colliders(scene: &Scene, camera: &Camera) -> Vec<Collider> {
    let mut state = SEED.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
    let mut next = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..COLLIDERS)
        .map(|_| {
            let (r, a, heading) =
                (REACH_M * next().sqrt(), std::f32::consts::TAU * next(), std::f32::consts::TAU * next());
            let (x, z) = (camera.position.x + r * a.cos(), camera.position.z + r * a.sin());
            Collider {
                center: Vec3::new(x, scene.ground(x, z) + RADIUS_M, z),
                radii: Vec3::splat(RADIUS_M),
                velocity: Vec3::new(heading.cos(), 0.0, heading.sin()) * SPEED_M_S,
            }
        })
        .collect()
}

/// The two scenes of the pairs: the default stored field and the unbounded block field.
pub fn scenes() -> (Scene, Scene) {
    let spec = FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 };
    (Scene::generate(STORED_BLADES, SEED), Scene::blocks(spec, SEED))
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(
    device: &Arc<Device>,
    options: &PairBenchOptions,
    progress: impl FnMut(u64, u64),
) -> Result<InteractionDocument> {
    let (stored, block) = scenes();
    let scenes = vec![stored.clone(), stored, block.clone(), block];
    let cameras: Vec<Camera> = scenes.iter().map(Scene::default_camera).collect();
    // Warm-up rounds (one step each) past a patch's longest life out of reach: the patches
    // measured are as many as a walk keeps, not the few of its first frames.
    let warmup = options.warmup.max(PATCH_WARMUP_ROUNDS);
    let schedule = Schedule { warmup, frames: options.frames };
    // The CLI's default: keyframes posed once per drawn blade with the cull (`--eval auto`).
    let plain = AnimationSettings { eval: Eval::default_for(true), ..AnimationSettings::default() };
    let animations: Vec<AnimationSettings> = (0..scenes.len())
        .map(|i| {
            let mut animation = plain.clone();
            if i % 2 == 1 {
                animation.wind.colliders = colliders(&scenes[i], &cameras[i]);
            }
            animation
        })
        .collect();
    // The measured rounds from `START_S`, the warm-up's steps before them.
    let step = 1.0 / 60.0;
    let start = (START_S - warmup as f32 * step).max(0.0);
    let animated = Animated { animations: &animations, start, step, settings: &[] };
    let pairs = pairs::run(device, (&PAIRS, &scenes, &cameras, animated), options.size, schedule, progress)?;
    Ok(InteractionDocument {
        header: Header::new(device, "interaction", options.size),
        warmup,
        frames: options.frames,
        colliders: COLLIDERS,
        radius_m: RADIUS_M,
        speed_m_s: SPEED_M_S,
        pairs,
    })
}

/// Write `interaction.json` into `dir`.
pub fn write(doc: &InteractionDocument, dir: &Path) -> Result<()> {
    crate::app::write_text(&dir.join(FILES[0]), &to_json(doc))
}

/// The pairs as a text table.
pub fn table(doc: &InteractionDocument) -> String {
    let head = format!("interaction, {} rounds after {} of warm-up\n", doc.frames, doc.warmup);
    let record = u64::from(crate::render::animation::patches::RECORD_WORDS) * 4;
    let store = crate::render::animation::patches::STORE_BYTES as f64 / (1 << 20) as f64;
    let patches: String = doc
        .pairs
        .iter()
        .filter_map(|p| p.subject.patches.map(|n| (&p.subject.name, n)))
        .map(|(name, n)| {
            let kib = (n * record) as f64 / 1024.0;
            format!("{name}: {n} blades hold patch state, {kib:.0} KiB of records (the store: {store:.0} MiB)\n")
        })
        .collect();
    head + &pairs::table_rows(&doc.pairs) + &patches
}
