//! `meadow bench --preset lod`: the GPU-driven cull and LOD against brute force. A row is a
//! label, a field and a view; for each, a brute-force and a GPU-driven renderer of the same scene
//! render the same camera at the same simulation time, interleaved (A B A B …, warm-up frames
//! discarded), each into its own target. Per row: both frame times, their ratio, the cull
//! passes' share of the GPU-driven frame, what the cull kept and drew, and how far the
//! GPU-driven picture is from brute force after an 8×8 box filter
//! ([`crate::imagediff::box_filtered_difference`]). Results go to `lod.json`, `lod.csv` and
//! `lod.png` ([`report`]).

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use crate::error::{Error, Result};
use crate::harness::document::{pass_times, Header, Summary};
use crate::harness::measure::{measure, Offscreen, Schedule};
use crate::harness::Progress;
use crate::imagediff::box_filtered_difference;
use crate::render::animation::{AnimationSettings, Eval};
use crate::render::culling::{CullCounts, Culling};
use crate::render::target::offscreen_bytes;
use crate::render::{FrameTimings, OffscreenTarget, RenderSettings, Renderer};
use crate::scene::camera::EYE_HEIGHT;
use crate::scene::{Camera, Scene, Terrain};
use crate::vk::Device;

pub mod document;
mod report;

pub use document::{
    CameraRecord, CountsRecord, DiffRecord, FieldRecord, LodDocument, LodFrame, LodMeasuredRow, LodOptionsRecord,
    LodVariant, Reference,
};
pub use report::{csv, plot, table, write, FILES};

/// Side in pixels of the blocks the pictures are averaged over before they are compared.
pub const DIFF_BLOCK: u32 = 8;
/// Simulation time of every frame, in seconds (`meadow render`'s default `--time`).
pub const SIMULATION_TIME: f32 = 0.0;
/// The variants of a row, in the order they render and appear in the document.
pub const VARIANTS: [&str; 2] = ["brute-force", "gpu-driven"];

/// The field a row renders.
#[derive(Clone, Debug, PartialEq)]
pub enum Field {
    /// Every blade stored: `Scene::generate(blades, seed)`.
    Stored {
        /// Blades of the field (it grows at a fixed density).
        blades: u32,
        /// Seed of the terrain and the scatter.
        seed: u64,
    },
    /// An unbounded field of camera-following blocks (`Scene::blocks`). It has no brute force (it
    /// is drawn only through the cull): its reference is today's default, the stored field of
    /// `REFERENCE_BLADES` by brute force from its default camera, and the pictures differ, so
    /// the row has no difference (`null`).
    Blocks {
        /// Blades per square metre.
        density: f32,
        /// Seed of the relief and the block.
        seed: u64,
    },
}

/// The stored field an unbounded field's row is measured against (the viewer's default).
pub const REFERENCE_BLADES: u32 = 100_000;

impl Field {
    /// Blades of the field.
    pub fn blades(&self) -> u32 {
        match self {
            Field::Stored { blades, .. } => *blades,
            Field::Blocks { density, .. } => self.spec(*density).block_blades() as u32,
        }
    }

    fn spec(&self, density: f32) -> crate::scene::field::FieldSpec {
        crate::scene::field::FieldSpec { size: None, density }
    }

    /// The field in the document.
    pub fn record(&self) -> FieldRecord {
        match self {
            Field::Stored { blades, seed } => FieldRecord::Stored { blades: *blades, seed: *seed },
            Field::Blocks { density, seed } => FieldRecord::Blocks {
                size: "infinite".into(),
                density: f64::from(*density),
                seed: *seed,
                reference: Reference { kind: "stored".into(), blades: REFERENCE_BLADES, view: "default".into() },
            },
        }
    }

    /// The scene each variant renders (brute force, GPU-driven).
    fn scenes(&self) -> [Scene; 2] {
        match self {
            Field::Stored { blades, seed } => {
                let scene = Scene::generate(*blades, *seed);
                [scene.clone(), scene]
            }
            Field::Blocks { density, seed } => {
                [Scene::generate(REFERENCE_BLADES, *seed), Scene::blocks(self.spec(*density), *seed)]
            }
        }
    }

    /// Every check of the field against the device before anything is allocated: each
    /// renderer's (`check_scene`), then two renderers and two targets together against the budget.
    fn check(&self, device: &Device, segments: u32, size: (u32, u32)) -> Result<()> {
        // Each row's brute-force renderer (per vertex, no cull) and GPU-driven one (culled).
        let scene = |blades: u32, culled: bool| {
            let animation = animation(culled);
            crate::app::check_scene(
                device,
                blades,
                segments,
                size,
                &animation,
                false,
                (culled, Default::default(), false),
            )
        };
        match self {
            Field::Stored { blades, .. } => {
                scene(*blades, false)?;
                scene(*blades, true)?;
                let cells = Terrain::cells_for(crate::scene::blades::field_size(*blades));
                let one = crate::render::scene_gpu::SceneGpu::memory_bytes(u64::from(*blades), u64::from(cells))
                    + offscreen_bytes(vk::Extent2D { width: size.0, height: size.1 });
                device.check_budget(2 * one, &format!("--preset lod with {blades} blades (two renderers)"))
            }
            Field::Blocks { .. } => {
                scene(REFERENCE_BLADES, false)?;
                scene(self.blades(), true)
            }
        }
    }
}

/// Where a row's camera stands, in proportion to its field's side `s` (so it frames any blade
/// count alike), on a field centred on the origin with north along −z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// `Camera::default_for`: 1.7 m above the middle of the south edge, looking north across the
    /// field, 12° down.
    Default,
    /// Standing (1.7 m) inside, a quarter of the side in from the south-west corner, looking
    /// north-east across the field to the far corner, 10° down.
    Inside,
    /// Above the middle of the south edge at s/4 over the ground, looking north 35° down.
    Above,
    /// Standing (1.7 m) on the east edge, s/20 in from the south-east corner, looking north along
    /// the edge (the field on the left half of the picture), 8° down.
    Edge,
}

impl View {
    /// Its name in the document.
    pub fn name(self) -> &'static str {
        match self {
            View::Default => "default",
            View::Inside => "inside",
            View::Above => "above",
            View::Edge => "edge",
        }
    }

    /// The camera on `terrain`.
    pub fn camera(self, terrain: &Terrain) -> Camera {
        let s = terrain.size;
        let stand = |x: f32, z: f32, above: f32, yaw_deg: f32, pitch_deg: f32| Camera {
            position: Vec3::new(x, terrain.height_at(x, z) + above, z),
            yaw_deg,
            pitch_deg,
        };
        match self {
            View::Default => Camera::default_for(terrain),
            View::Inside => stand(-0.25 * s, 0.25 * s, EYE_HEIGHT, -45.0, -10.0),
            View::Above => stand(0.0, 0.5 * s, 0.25 * s, 0.0, -35.0),
            View::Edge => stand(0.5 * s, 0.45 * s, EYE_HEIGHT, 0.0, -8.0),
        }
    }
}

/// One row: what it is called, the field, where the camera stands.
#[derive(Clone, Debug, PartialEq)]
pub struct LodRow {
    /// Name in the table, the CSV and the plot.
    pub label: String,
    /// The field.
    pub field: Field,
    /// The camera.
    pub view: View,
}

impl LodRow {
    /// A row.
    pub fn new(label: &str, field: Field, view: View) -> Self {
        Self { label: label.into(), field, view }
    }
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct LodBenchOptions {
    /// The rows, measured in order; consecutive rows of the same field share its renderers.
    pub rows: Vec<LodRow>,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// Segments of brute force, and of the GPU-driven path's nearest LOD bucket.
    pub segments: u32,
    /// Output directory.
    pub out: PathBuf,
}

impl LodBenchOptions {
    /// `--preset lod`: a stored field of a million blades, 4 segments, 1280×720, from four views.
    pub fn preset(out: PathBuf) -> Self {
        let stored = Field::Stored { blades: 1_000_000, seed: 1 };
        let unbounded = Field::Blocks { density: crate::scene::blades::DENSITY_PER_M2, seed: 1 };
        Self {
            // One line per (field, view).
            rows: vec![
                LodRow::new("stored, default", stored.clone(), View::Default),
                LodRow::new("stored, inside", stored.clone(), View::Inside),
                LodRow::new("stored, above", stored.clone(), View::Above),
                LodRow::new("stored, edge", stored, View::Edge),
                LodRow::new("unbounded (vs 100k)", unbounded, View::Default),
            ],
            size: (1280, 720),
            warmup: 1,
            frames: 9,
            segments: 4,
            out,
        }
    }

    /// Replace the blade count of every stored field (`--blades`).
    pub fn set_stored_blades(&mut self, count: u32) {
        for row in &mut self.rows {
            if let Field::Stored { blades, .. } = &mut row.field {
                *blades = count;
            }
        }
    }

    /// The options as the document records them.
    fn record(&self) -> LodOptionsRecord {
        LodOptionsRecord {
            rows: self.rows.len(),
            size: [self.size.0, self.size.1],
            warmup: self.warmup,
            frames: self.frames,
            segments: self.segments,
            simulation_time_s: f64::from(SIMULATION_TIME),
            diff_block: DIFF_BLOCK,
        }
    }
}

/// Run the benchmark; `progress(done, total)` after every frame. Returns the document.
pub fn run(device: &Arc<Device>, options: &LodBenchOptions, mut progress: impl FnMut(u64, u64)) -> Result<LodDocument> {
    if options.rows.is_empty() {
        return Err(Error::bad_input("nothing to measure: no rows"));
    }
    if options.size.0 < DIFF_BLOCK || options.size.1 < DIFF_BLOCK {
        return Err(Error::bad_input(format!(
            "--size {}x{}: --preset lod compares pictures in {DIFF_BLOCK}x{DIFF_BLOCK} blocks and needs at least one",
            options.size.0, options.size.1
        )));
    }
    // Every row's limits before the output directory exists: bad input leaves no empty directory.
    for row in &options.rows {
        row.field.check(device, options.segments, options.size)?;
    }
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let total = (options.rows.len() * VARIANTS.len()) as u64 * u64::from(options.warmup + options.frames);
    let mut frames = Progress::new(total, &mut progress);
    let mut targets = Vec::new();
    let rows = (|| {
        for _ in VARIANTS {
            targets.push(OffscreenTarget::new(device, extent)?);
        }
        measure_rows(device, options, &mut targets, &mut frames)
    })();
    for target in targets {
        // SAFETY: measure_rows dropped its renderers, which waited for their frames.
        unsafe { target.destroy(device) };
    }
    Ok(LodDocument {
        header: Header::new(device, "lod", options.size),
        options: options.record(),
        warmup: options.warmup,
        frames_per_variant: options.frames,
        rows: rows?,
    })
}

/// The renderers of one field: brute force and GPU-driven, in the order of [`VARIANTS`].
struct Built {
    field: Field,
    scenes: [Scene; 2],
    renderers: Vec<Renderer>,
}

/// Measure every row, building a field's scene and renderers when it differs from the previous
/// row's. The renderers are dropped (their frames waited for) before this returns.
fn measure_rows(
    device: &Arc<Device>,
    options: &LodBenchOptions,
    targets: &mut [OffscreenTarget],
    frames: &mut Progress,
) -> Result<Vec<LodMeasuredRow>> {
    let mut built: Option<Built> = None;
    let mut rows = Vec::new();
    for row in &options.rows {
        if built.as_ref().is_none_or(|b| b.field != row.field) {
            // The previous field's renderers go first: only one field is on the device at once.
            drop(built.take());
            built = Some(build(device, &row.field, options.segments)?);
        }
        let b = built.as_mut().expect("built above");
        rows.push(measure_row(row, &b.scenes, &mut b.renderers, targets, options, frames)?);
    }
    Ok(rows)
}

/// A variant's animation: texture keyframes without wind (`AnimationSettings::default()`),
/// evaluated where its path does by default (`Eval::default_for`, as `--eval auto`: per vertex by
/// brute force, once per drawn blade with the cull).
fn animation(culled: bool) -> AnimationSettings {
    AnimationSettings { eval: Eval::default_for(culled), ..AnimationSettings::default() }
}

/// The scene of `field` and its two renderers, each with its path's `animation`, one frame in
/// flight, pipeline statistics off.
fn build(device: &Arc<Device>, field: &Field, segments: u32) -> Result<Built> {
    let scenes = field.scenes();
    let renderers = [Culling::brute_force(segments), Culling::default_for(segments)]
        .into_iter()
        .zip(&scenes)
        .map(|(culling, scene)| {
            let settings = RenderSettings::offscreen(segments, culling);
            Renderer::new(device.clone(), scene, settings, animation(culling.enabled))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Built { field: field.clone(), scenes, renderers })
}

impl LodFrame {
    /// The frame of `t`: its GPU time, its cull passes' (those whose name starts with "cull").
    fn of(t: &FrameTimings) -> Self {
        let cull_ms = t.passes.iter().filter(|p| p.name.starts_with("cull")).fold(0.0, |sum, p| sum + p.ms);
        Self { gpu_ms: t.gpu_ms, cull_ms, passes_ms: pass_times(&t.passes) }
    }

    /// The cull passes' share of the frame (0 for a frame without GPU time).
    fn cull_share(&self) -> f64 {
        if self.gpu_ms > 0.0 {
            self.cull_ms / self.gpu_ms
        } else {
            0.0
        }
    }
}

/// One row: both variants rendered interleaved from the row's camera, then their last pictures
/// compared. Returns the row.
fn measure_row(
    row: &LodRow,
    scenes: &[Scene; 2],
    renderers: &mut [Renderer],
    targets: &mut [OffscreenTarget],
    options: &LodBenchOptions,
    frames: &mut Progress,
) -> Result<LodMeasuredRow> {
    // A stored field's view; an unbounded field's (and its reference's) default camera.
    let cameras = scenes.each_ref().map(|scene| match scene.field {
        Some(_) => scene.default_camera(),
        None if matches!(row.field, Field::Blocks { .. }) => scene.default_camera(),
        None => row.view.camera(&scene.terrain),
    });
    let camera = cameras[1];
    let mut subject =
        Offscreen { renderers, targets, camera: &|i, _| cameras[i], time: &|_| SIMULATION_TIME, after: None };
    let measured = measure(&mut subject, Schedule { warmup: options.warmup, frames: options.frames }, frames)?;
    let (renderers, targets) = (subject.renderers, subject.targets);
    let samples: Vec<Vec<LodFrame>> = (0..2).map(|i| measured.timings(i).map(LodFrame::of).collect()).collect();
    // The GPU-driven renderer's last frame, warm-up or not.
    let cull = measured.all(1).last().and_then(|f| f.timings.cull);
    let cull = cull.ok_or_else(|| Error::Internal("the GPU-driven renderer read back no cull counts".into()))?;
    let rgb =
        |t: &OffscreenTarget| -> Vec<u8> { t.pixels().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect() };
    let (w, h) = options.size;
    let diff = box_filtered_difference(&rgb(&targets[0]), &rgb(&targets[1]), w, h, DIFF_BLOCK);
    let brute_triangles = renderers[0].triangles().0;
    let [brute, culled]: [Vec<LodFrame>; 2] = samples.try_into().expect("two variants");
    let variants = vec![
        variant(VARIANTS[0], brute, scenes[0].blades.len() as u64, brute_triangles, None),
        variant(VARIANTS[1], culled, cull.total_drawn(), cull.triangles(), Some(counts(&cull))),
    ];
    let median = |v: &LodVariant| v.gpu_ms.median;
    let ratio = if median(&variants[1]) > 0.0 { median(&variants[0]) / median(&variants[1]) } else { 0.0 };
    let position = camera.position.to_array().map(f64::from);
    Ok(LodMeasuredRow {
        label: row.label.clone(),
        field: row.field.record(),
        blades: row.field.blades(),
        segments: options.segments,
        view: row.view.name().into(),
        camera: CameraRecord { position, yaw_deg: f64::from(camera.yaw_deg), pitch_deg: f64::from(camera.pitch_deg) },
        ratio,
        cull_share: variants[1].cull_share,
        // Pictures of two different scenes are not compared.
        diff: (!matches!(row.field, Field::Blocks { .. })).then_some(DiffRecord {
            block: DIFF_BLOCK,
            mean_percent: diff.mean_percent,
            p99_percent: diff.p99_percent,
            max_percent: diff.max_percent,
        }),
        variants,
    })
}

/// A variant's entry of a row: its frame times, what it drew, its cull counts (GPU-driven only)
/// and its measured frames.
fn variant(name: &str, frames: Vec<LodFrame>, drawn: u64, triangles: u64, counts: Option<CountsRecord>) -> LodVariant {
    let of = |f: fn(&LodFrame) -> f64| Summary::of(&frames.iter().map(f).collect::<Vec<f64>>());
    LodVariant {
        variant: name.into(),
        gpu_ms: of(|f| f.gpu_ms),
        cull_ms: of(|f| f.cull_ms),
        // The median over the frames of each frame's cull passes / its GPU time.
        cull_share: of(LodFrame::cull_share).median,
        drawn_blades: drawn,
        blade_triangles: triangles,
        counts,
        frames,
    }
}

/// What the cull kept after each test and drew per bucket.
fn counts(c: &CullCounts) -> CountsRecord {
    let buckets = c.segments.iter().take_while(|&&s| s > 0).count();
    CountsRecord {
        considered: c.considered,
        after_tiles: c.after_tiles,
        after_density: c.after_density,
        after_frustum: c.after_frustum,
        after_orientation: c.after_orientation,
        after_occlusion: c.after_occlusion,
        tiles_visible: c.tiles_visible,
        tiles: c.tiles,
        drawn: c.drawn[..buckets].to_vec(),
        bucket_segments: c.segments[..buckets].to_vec(),
        total_drawn: c.total_drawn(),
        triangles: c.triangles(),
        classes: crate::harness::document::ClassDrawn::of(c),
        thinning: Some(crate::harness::document::Thinning::of(c)),
    }
}
