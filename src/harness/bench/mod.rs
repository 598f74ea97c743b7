//! `meadow bench`: thesis Table 6.2 reproduced on this device. For each (blades, segments) row
//! every variant (static, floor, texture and uniform keyframes per evaluation placement) is built
//! once and the variants are rendered interleaved, A B C A B C …, so their ratios survive a noisy
//! machine. Results go to `bench.json` (versioned, every frame), `bench.csv` (tidy) and a table.

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::target::offscreen_bytes;
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::{Device, Guard};

pub mod animations;
mod compare;
pub mod document;
pub mod far;
pub mod far_pictures;
pub mod interaction;
pub mod landscape;
pub mod lod;
pub mod msaa;
pub mod pairs;
pub mod plants;
mod report;
pub mod response;

pub use compare::{compare, load};
pub use document::{BenchDocument, BenchFrame, BenchRow, BenchVariant, VariantMeasured};
pub use report::{best, csv, median, plot, statistics_table, table, write, FILES};

use crate::harness::document::{Header, Outcome};
use crate::harness::measure::{measure, Offscreen, Schedule};
use crate::harness::Progress;

/// Thesis Table 6.2: (blades, segments, FPS N, FPS T, FPS U) on a GeForce 8800 GTS.
pub const THESIS_TABLE: [(u32, u32, f64, f64, f64); 15] = [
    (40_000, 4, 433.0, 400.0, 364.0),
    (160_000, 4, 206.0, 170.0, 155.0),
    (360_000, 4, 98.0, 78.0, 69.0),
    (640_000, 4, 58.0, 47.0, 40.0),
    (1_000_000, 4, 39.0, 28.0, 25.0),
    (40_000, 8, 365.0, 328.0, 305.0),
    (160_000, 8, 111.0, 98.0, 92.0),
    (360_000, 8, 57.0, 44.0, 41.0),
    (640_000, 8, 33.0, 25.0, 23.0),
    (1_000_000, 8, 23.0, 16.0, 15.0),
    (40_000, 16, 214.0, 198.0, 177.0),
    (160_000, 16, 58.0, 52.0, 46.0),
    (360_000, 16, 31.0, 24.0, 21.0),
    (640_000, 16, 18.0, 13.0, 12.0),
    (1_000_000, 16, 12.0, 8.0, 7.0),
];

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// (blades, segments) rows.
    pub rows: Vec<(u32, u32)>,
    /// Modes.
    pub modes: Vec<Column>,
    /// Evaluation placements (keyframed modes only).
    pub evals: Vec<Eval>,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
    /// The fixed time step: frame n of a variant is drawn at n · dt (`render::animation::clock`;
    /// the default 1/60 s, which the thesis and quick presets keep so their rows compare).
    pub dt: f64,
}

impl BenchOptions {
    /// `--preset thesis`: the 15 rows of Table 6.2 at 1280×720.
    pub fn thesis(out: PathBuf) -> Self {
        Self {
            rows: THESIS_TABLE.iter().map(|r| (r.0, r.1)).collect(),
            modes: Column::ALL.to_vec(),
            evals: vec![Eval::Vertex, Eval::Blade],
            size: (1280, 720),
            // 15 rows x 6 variants x 6 rounds: about 20 minutes on 2 cores with lavapipe.
            warmup: 1,
            frames: 5,
            out,
            dt: crate::render::animation::clock::DEFAULT_DT,
        }
    }

    /// `--preset quick`: a small matrix for smoke runs.
    pub fn quick(out: PathBuf) -> Self {
        Self {
            rows: vec![(10_000, 4), (20_000, 8)],
            modes: Column::ALL.to_vec(),
            evals: vec![Eval::Vertex, Eval::Blade],
            size: (320, 180),
            warmup: 1,
            frames: 3,
            out,
            dt: crate::render::animation::clock::DEFAULT_DT,
        }
    }
}

/// A column of Table 6.2: blades animated by a mode, or the floor reference pass (which is a
/// render setting, not an animation: `RenderSettings::floor`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    /// Blades animated by this mode.
    Animated(Mode),
    /// The floor: the static blades' triangles pre-expanded, transform and flat colour only.
    Floor,
}

impl Column {
    /// Static, texture, uniform, floor.
    pub const ALL: [Column; 4] = [
        Column::Animated(Mode::Static),
        Column::Animated(Mode::Texture),
        Column::Animated(Mode::Uniform),
        Column::Floor,
    ];

    /// The animation mode (static for the floor).
    pub fn mode(self) -> Mode {
        match self {
            Column::Animated(mode) => mode,
            Column::Floor => Mode::Static,
        }
    }
}

/// One variant of a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// Mode.
    pub mode: Column,
    /// Evaluation placement.
    pub eval: Eval,
}

impl Variant {
    /// `texture/blade`, `static`, `floor`…
    pub fn name(&self) -> String {
        match self.mode {
            Column::Floor => "floor".into(),
            Column::Animated(Mode::Static) => "static".into(),
            Column::Animated(mode) => {
                format!("{}/{}", format!("{mode:?}").to_lowercase(), format!("{:?}", self.eval).to_lowercase())
            }
        }
    }
}

/// The variants of `options`: static and floor once, keyframed modes per evaluation placement.
pub fn variants(options: &BenchOptions) -> Vec<Variant> {
    let mut out = Vec::new();
    for mode in &options.modes {
        match mode {
            Column::Floor | Column::Animated(Mode::Static) => out.push(Variant { mode: *mode, eval: Eval::Vertex }),
            _ => out.extend(options.evals.iter().map(|eval| Variant { mode: *mode, eval: *eval })),
        }
    }
    out
}

/// Run the benchmark; `progress(done, total)` after every frame. Returns the document.
pub fn run(device: &Arc<Device>, options: &BenchOptions, mut progress: impl FnMut(u64, u64)) -> Result<BenchDocument> {
    let variants = variants(options);
    if variants.is_empty() || options.rows.is_empty() {
        return Err(Error::bad_input("nothing to measure: give at least one mode and one row"));
    }
    // Every row's limits before the output directory exists: bad input leaves no empty directory.
    for &(blades, _) in &options.rows {
        let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
        crate::app::check_limits(device, blades, (options.size, Default::default(), false), cells)?;
    }
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let total = (options.rows.len() * variants.len()) as u64 * u64::from(options.warmup + options.frames);
    let mut frames = Progress::new(total, &mut progress);
    let mut rows = Vec::new();
    for &(blades, segments) in &options.rows {
        rows.push(measure_row(device, options, &variants, (blades, segments), &mut frames)?);
    }
    Ok(BenchDocument {
        header: Header::new(device, "bench", options.size),
        warmup: options.warmup,
        frames_per_variant: options.frames,
        dt_s: Some(options.dt),
        memory_per_row_bytes: offscreen_bytes(extent),
        rows,
    })
}

/// One row of the table: every variant the device supports at (`blades`, `segments`) built, then
/// rendered interleaved. Returns the row, unsupported variants included with the reason.
fn measure_row(
    device: &Arc<Device>,
    options: &BenchOptions,
    variants: &[Variant],
    (blades, segments): (u32, u32),
    frames: &mut Progress,
) -> Result<BenchRow> {
    let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
    crate::app::check_limits(device, blades, (options.size, Default::default(), false), cells)?;
    let scene = Scene::generate(blades, 1);
    let camera = scene.default_camera();
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    // Destroyed when the row is done or fails (after the renderers, which wait for their frames).
    let mut target = Guard::new(device, OffscreenTarget::new(device, extent)?);
    // A variant the device cannot hold at this size (e.g. `--eval blade`'s records over
    // maxStorageBufferRange) is reported as unsupported for the row, not failed.
    let mut unsupported = Vec::new();
    let runnable: Vec<Variant> = variants
        .iter()
        .copied()
        .filter(|v| {
            match crate::app::check_scene(
                device,
                blades,
                segments,
                options.size,
                &animation_of(v),
                v.mode == Column::Floor,
                (false, Default::default(), false),
            ) {
                Err(Error::BadInput(why)) => {
                    unsupported
                        .push(BenchVariant { variant: v.name(), outcome: Outcome::Unsupported { unsupported: why } });
                    frames.skipped(u64::from(options.warmup + options.frames));
                    false
                }
                _ => true,
            }
        })
        .collect();
    let mut renderers = build_renderers(device, &scene, segments, &runnable)?;
    let measured = render_interleaved(&mut renderers, &mut target, &camera, options, frames);
    let triangles = renderers.first().map_or(0, |r| r.triangles().0);
    // Every renderer waits for its frames when dropped: then nothing uses the target.
    drop(renderers);
    drop(target);
    let measured = measured?;
    let mut entries: Vec<BenchVariant> = runnable
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let frames = measured.timings(i).map(BenchFrame::of).collect();
            BenchVariant { variant: v.name(), outcome: Outcome::Measured(VariantMeasured::of(frames)) }
        })
        .collect();
    entries.extend(unsupported);
    Ok(BenchRow { blades, segments, triangles, variants: entries })
}

/// A renderer per variant, all into the offscreen format with pipeline statistics.
fn build_renderers(device: &Arc<Device>, scene: &Scene, segments: u32, variants: &[Variant]) -> Result<Vec<Renderer>> {
    variants
        .iter()
        .map(|v| {
            let animation = animation_of(v);
            // The thesis benchmark measures every stored blade at full detail.
            let settings = RenderSettings {
                pipeline_statistics: true,
                floor: v.mode == Column::Floor,
                ..RenderSettings::offscreen(segments, crate::render::culling::Culling::brute_force(segments))
            };
            Renderer::new(device.clone(), scene, settings, animation)
        })
        .collect()
}

/// The measuring loop over `renderers`, into one target, from one camera, at a fixed simulation
/// time step (round n at n / 60 s).
fn render_interleaved(
    renderers: &mut [Renderer],
    target: &mut OffscreenTarget,
    camera: &Camera,
    options: &BenchOptions,
    frames: &mut Progress,
) -> Result<crate::harness::measure::Measured> {
    let mut subject = Offscreen {
        renderers,
        targets: std::slice::from_mut(target),
        camera: &|_, _| *camera,
        time: &|round| (f64::from(round) * options.dt) as f32,
        after: None,
    };
    measure(&mut subject, Schedule { warmup: options.warmup, frames: options.frames }, frames)
}

/// The animation of a variant: the CLI's default wind (30°, strength 0.3, gusts).
fn animation_of(v: &Variant) -> AnimationSettings {
    AnimationSettings {
        mode: v.mode.mode(),
        eval: v.eval,
        wind: crate::wind::Wind {
            global: Some(crate::wind::GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: true }),
            ..Default::default()
        },
        ..Default::default()
    }
}
