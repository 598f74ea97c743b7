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

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::document::{to_json, Header, Summary};
use crate::harness::measure::{measure, Measured, Offscreen, Schedule};
use crate::harness::Progress;
use crate::imagediff::compare_rgb;
use crate::render::animation::AnimationSettings;
use crate::render::culling::Culling;
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
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
/// Segments of the blades.
pub const SEGMENTS: u32 = 4;
/// The seed of the relief and the block.
pub const SEED: u64 = 1;

/// The options of a run.
#[derive(Clone, Debug)]
pub struct LandscapeBenchOptions {
    /// Picture size.
    pub size: (u32, u32),
    /// Rounds discarded first.
    pub warmup: u32,
    /// Rounds measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
}

impl LandscapeBenchOptions {
    /// The preset: 1280×720, 2 + 10 rounds.
    pub fn preset(out: PathBuf) -> Self {
        Self { size: (1280, 720), warmup: 2, frames: 10, out }
    }
}

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

/// A reference and a subject measured against it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pair {
    /// What is compared.
    pub label: String,
    pub reference: Variant,
    pub subject: Variant,
    /// The subject's median GPU frame over the reference's.
    pub ratio: f64,
    /// The bound on the ratio, and whether the ratio is within it.
    pub target: f64,
    pub within_target: bool,
    /// Of the last pictures: the fraction of pixels within ±3 and the largest difference (0–255).
    pub within_3: f64,
    pub max_diff: u8,
}

/// One renderer's measured frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variant {
    pub name: String,
    /// x, y, z, yaw, pitch.
    pub camera: [f32; 5],
    pub gpu_ms: Summary,
    /// Blades drawn in the last frame.
    pub drawn: u64,
}

/// The pairs' (label, reference name, subject name, target).
const PAIRS: [(&str, &str, &str, f64); 3] = [
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
    let cover = |width, grass| {
        let map = CoverMap { width, height: 1, grass, placement };
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
    options: &LandscapeBenchOptions,
    progress: impl FnMut(u64, u64),
) -> Result<LandscapeDocument> {
    let (scenes, export_texels, export_ms) = scenes();
    let cameras = cameras(&scenes);
    let schedule = Schedule { warmup: options.warmup, frames: options.frames };
    let (measured, pictures) = render(device, (&scenes, &cameras), options.size, schedule, progress)?;
    let variant = |i: usize| {
        let gpu: Vec<f64> = measured.timings(i).map(|t| t.gpu_ms).collect();
        let drawn = measured.all(i).last().and_then(|f| f.timings.cull).map_or(0, |c| c.total_drawn());
        let c = cameras[i];
        let name = [PAIRS[i / 2].1, PAIRS[i / 2].2][i % 2].to_string();
        let camera = [c.position.x, c.position.y, c.position.z, c.yaw_deg, c.pitch_deg];
        Variant { name, camera, gpu_ms: Summary::of(&gpu), drawn }
    };
    let pairs = PAIRS
        .iter()
        .enumerate()
        .map(|(p, &(label, _, _, target))| {
            let (reference, subject) = (variant(2 * p), variant(2 * p + 1));
            let ratio = subject.gpu_ms.median / reference.gpu_ms.median;
            let (stats, _) = compare_rgb(&pictures[2 * p], &pictures[2 * p + 1], 3);
            let (within_3, max_diff) = (stats.within_fraction(), stats.max_diff);
            Pair {
                label: label.into(),
                reference,
                subject,
                ratio,
                target,
                within_target: ratio <= target,
                within_3,
                max_diff,
            }
        })
        .collect();
    Ok(LandscapeDocument {
        header: Header::new(device, "landscape", options.size),
        warmup: options.warmup,
        frames: options.frames,
        export_texels,
        export_ms,
        pairs,
    })
}

/// Render the six `scenes` from their `cameras` in turn, `schedule`'s rounds of `size` pictures:
/// every frame's timings, and each variant's last picture (RGB8).
fn render(
    device: &Arc<Device>,
    (scenes, cameras): (&[Scene; 6], &[Camera]),
    size: (u32, u32),
    schedule: Schedule,
    mut progress: impl FnMut(u64, u64),
) -> Result<(Measured, Vec<Vec<u8>>)> {
    let settings = RenderSettings {
        pipeline_statistics: true,
        ..RenderSettings::offscreen(SEGMENTS, Culling::default_for(SEGMENTS))
    };
    let mut renderers = Vec::new();
    for scene in scenes {
        renderers.push(Renderer::new(device.clone(), scene, settings, AnimationSettings::default())?);
    }
    let mut targets = vec![OffscreenTarget::new(device, vk::Extent2D { width: size.0, height: size.1 })?];
    let mut frames = Progress::new(6 * u64::from(schedule.rounds()), &mut progress);
    let mut pictures: Vec<Vec<u8>> = vec![Vec::new(); 6];
    let last = schedule.rounds() - 1;
    let mut round_of = [0u32; 6];
    let measured = {
        let mut after = |i: usize, target: &OffscreenTarget| {
            if round_of[i] == last {
                pictures[i] = target.pixels().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
            }
            round_of[i] += 1;
        };
        let camera = |i: usize, _| cameras[i];
        let time = |_| 0.0;
        let mut subject = Offscreen {
            renderers: &mut renderers,
            targets: &mut targets,
            camera: &camera,
            time: &time,
            after: Some(&mut after),
        };
        measure(&mut subject, schedule, &mut frames)
    };
    drop(renderers);
    for target in targets {
        // SAFETY: every renderer waited for its frames and is dropped.
        unsafe { target.destroy(device) };
    }
    Ok((measured?, pictures))
}

/// Write `landscape.json` into `dir`.
pub fn write(doc: &LandscapeDocument, dir: &Path) -> Result<()> {
    crate::app::write_text(&dir.join(FILES[0]), &to_json(doc))
}

/// The pairs as a text table.
pub fn table(doc: &LandscapeDocument) -> String {
    let mut out = format!(
        "landscape, {} rounds after {} of warm-up; the exported relief: {} x {} texels, made in {:.0} ms\n",
        doc.frames, doc.warmup, doc.export_texels, doc.export_texels, doc.export_ms
    );
    out.push_str("pair | reference ms | subject ms | ratio (target) | drawn | pixels within ±3, largest difference\n");
    for p in &doc.pairs {
        let met = if p.within_target { "met" } else { "missed" };
        out.push_str(&format!(
            "{} | {:.1} | {:.1} | {:.3}x (<= {}, {met}) | {} / {} | {:.3} %, {}\n",
            p.label,
            p.reference.gpu_ms.median,
            p.subject.gpu_ms.median,
            p.ratio,
            p.target,
            p.reference.drawn,
            p.subject.drawn,
            100.0 * p.within_3,
            p.max_diff
        ));
    }
    out
}
