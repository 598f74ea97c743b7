//! `meadow bench --preset animations`: the blade responses side by side on the same fields,
//! cameras and frame budget (issue "The companion blade models"). Per row, one renderer per
//! response renders the same scene, interleaved (A B C A B C …, warm-up discarded), one step a
//! frame (frame k at k · dt):
//!
//! - the culled stored field (100 000 blades, the viewer's default) and the unbounded block field,
//!   every response;
//! - the thesis' sizes by brute force (360 000 × 8 and 1 000 000 × 4), the stateless responses
//!   (a stateful one, Verlet, is stepped in a store sized for what the cull draws).
//!
//! Each variant records its median GPU ms, its ratio to static drawn the same way, and its own
//! passes' time (`Renderer::response_passes`) per step, so the viewer's several steps a frame can
//! be predicted. Every row reads the analytic wind field; each other field of `--wind-fields`
//! adds the culled rows again, where the keyframes and the Verlet blades are measured under both
//! fields side by side (interleaved, static under the analytic field the reference). Results go
//! to `animations.json` and `animations.csv` ([`report`]).

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::harness::document::{Header, Summary};
use crate::harness::measure::{measure, Offscreen, Schedule};
use crate::harness::Progress;
use crate::render::animation::sine::SinePhase;
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::culling::Culling;
use crate::render::wind::FieldKind;
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::field::FieldSpec;
use crate::scene::Scene;
use crate::vk::Device;

pub mod document;
mod report;

pub use document::{AnimationsDocument, AnimationsOptionsRecord, AnimationsRow, AnimationsVariant};
pub use report::{csv, table, write, FILES};

/// The fixed step of every run (`--dt`'s default): one step a frame.
pub const DT: f64 = 1.0 / 60.0;
/// Segments of the culled rows' blades (`meadow render`'s default).
pub const SEGMENTS: u32 = 4;

/// The options of a run.
#[derive(Clone, Debug)]
pub struct AnimationsBenchOptions {
    /// The responses, in order; static is added first when missing (every ratio's reference).
    pub animations: Vec<Mode>,
    /// Blades of the culled stored field.
    pub blades: u32,
    /// The brute-force rows: (blades, segments).
    pub brute_force: Vec<(u32, u32)>,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per variant discarded first.
    pub warmup: u32,
    /// Frames per variant measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
    /// Wind fields besides the analytic one: each adds the culled rows under it.
    pub wind_fields: Vec<FieldKind>,
}

impl AnimationsBenchOptions {
    /// The preset: every response, the viewer's default field and the thesis' sizes, 1280×720.
    pub fn preset(out: PathBuf) -> Self {
        Self {
            animations: vec![
                Mode::Static,
                Mode::Texture,
                Mode::Sine(SinePhase::Object),
                Mode::Sine(SinePhase::Vertex),
                Mode::Sine(SinePhase::Cluster),
                Mode::Verlet,
                Mode::Inertial,
                Mode::VirtualInertial,
            ],
            blades: 100_000,
            brute_force: vec![(360_000, 8), (1_000_000, 4)],
            size: (1280, 720),
            warmup: 2,
            frames: 24,
            out,
            wind_fields: Vec::new(),
        }
    }

    /// Replace every stored field's blade count (`--blades`): the culled row's and the
    /// brute-force rows' (which keep their segments).
    pub fn set_blades(&mut self, blades: u32) {
        self.blades = blades;
        self.brute_force.iter_mut().for_each(|row| row.0 = blades);
    }

    /// The responses with static first.
    fn responses(&self) -> Vec<Mode> {
        let mut out = vec![Mode::Static];
        out.extend(self.animations.iter().copied().filter(|&m| m != Mode::Static));
        out
    }
}

/// The `--animation` value of a response's mode (keyframes: the texture, the default).
pub fn animation_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Static => "static",
        Mode::Texture | Mode::Uniform => "keyframes",
        Mode::Sine(SinePhase::Object) => "sine-object",
        Mode::Sine(SinePhase::Vertex) => "sine-vertex",
        Mode::Sine(SinePhase::Cluster) => "sine-cluster",
        Mode::Verlet => "verlet",
        Mode::Inertial => "inertial",
        Mode::VirtualInertial => "virtual-inertial",
    }
}

/// A row: its label, its scene, how it is drawn (culled or not) and its segments.
struct Row {
    label: String,
    scene: SceneSource,
    culled: bool,
    segments: u32,
    field: FieldKind,
}

impl Row {
    /// The variants it measures, each a response under a field: by brute force the stateless
    /// responses only; in a row of a field other than the analytic one, static (the ratios'
    /// reference), then the keyframes and Verlet under the analytic field and under the row's.
    fn responses(&self, responses: &[Mode]) -> Vec<(Mode, FieldKind)> {
        let analytic = FieldKind::Analytic;
        let kept = responses.iter().copied().filter(|&m| self.culled || !stateful(m));
        if self.field == analytic {
            return kept.map(|m| (m, analytic)).collect();
        }
        kept.flat_map(|m| match m {
            Mode::Static => vec![(m, analytic)],
            Mode::Texture | Mode::Verlet => vec![(m, analytic), (m, self.field)],
            _ => Vec::new(),
        })
        .collect()
    }
}

/// Whether `mode`'s response keeps state per blade (a store sized for what the cull draws; the
/// virtually-inertial blades keep theirs per wind corner, and are measured by brute force too).
fn stateful(mode: Mode) -> bool {
    matches!(mode, Mode::Verlet | Mode::Inertial)
}

/// Where a row's scene comes from.
#[derive(Clone, Copy)]
enum SceneSource {
    Stored(u32),
    Blocks,
}

impl SceneSource {
    fn scene(self) -> Scene {
        match self {
            SceneSource::Stored(blades) => Scene::generate(blades, 1),
            SceneSource::Blocks => {
                Scene::blocks(FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 }, 1)
            }
        }
    }

    /// Blades stored (a block field's: one block's).
    fn blades(self) -> u32 {
        match self {
            SceneSource::Stored(blades) => blades,
            SceneSource::Blocks => {
                FieldSpec { size: None, density: crate::scene::blades::DENSITY_PER_M2 }.block_blades() as u32
            }
        }
    }
}

fn rows(options: &AnimationsBenchOptions) -> Vec<Row> {
    let blades = options.blades;
    let culled = |field: FieldKind| {
        let under = if field == FieldKind::Analytic { String::new() } else { format!(", {}", field.name()) };
        [
            Row {
                label: format!("{blades} stored, culled{under}"),
                scene: SceneSource::Stored(blades),
                culled: true,
                segments: SEGMENTS,
                field,
            },
            Row {
                label: format!("unbounded field{under}"),
                scene: SceneSource::Blocks,
                culled: true,
                segments: SEGMENTS,
                field,
            },
        ]
    };
    let mut rows: Vec<Row> = culled(FieldKind::Analytic).into_iter().collect();
    for &(blades, segments) in &options.brute_force {
        let label = format!("{blades} x {segments}, brute force");
        rows.push(Row {
            label,
            scene: SceneSource::Stored(blades),
            culled: false,
            segments,
            field: FieldKind::Analytic,
        });
    }
    for &field in &options.wind_fields {
        rows.extend(culled(field));
    }
    rows
}

/// The animation settings of `mode` drawn with or without the cull, under `field`.
fn animation(mode: Mode, culled: bool, field: FieldKind) -> AnimationSettings {
    AnimationSettings { mode, eval: Eval::default_for(culled), wind_field: field, ..AnimationSettings::default() }
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(
    device: &Arc<Device>,
    options: &AnimationsBenchOptions,
    progress: impl FnMut(u64, u64),
) -> Result<AnimationsDocument> {
    let responses = options.responses();
    let rows = rows(options);
    check(device, options, &rows, &responses)?;
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let rounds = u64::from(options.warmup + options.frames);
    let mut progress = progress;
    let variants: u64 = rows.iter().map(|row| row.responses(&responses).len() as u64).sum();
    let mut frames = Progress::new(variants * rounds, &mut progress);
    let mut target = OffscreenTarget::new(device, extent)?;
    let measured = rows
        .iter()
        .map(|row| measure_row(device, row, &row.responses(&responses), &mut target, options, &mut frames))
        .collect::<Result<Vec<_>>>();
    // SAFETY: measure_row dropped its renderers, which waited for their frames.
    unsafe { target.destroy(device) };
    let recorded = AnimationsOptionsRecord {
        animations: responses.iter().map(|&m| animation_name(m).to_string()).collect(),
        size: [options.size.0, options.size.1],
        warmup: options.warmup,
        frames: options.frames,
        dt_s: DT,
    };
    Ok(AnimationsDocument {
        header: Header::new(device, "animations", options.size),
        options: recorded,
        rows: measured?,
    })
}

/// Every check against the device before anything is built: each row's scene under each
/// response (`app::check_scene`), then a row's renderers together against the memory budget.
fn check(device: &Device, options: &AnimationsBenchOptions, rows: &[Row], responses: &[Mode]) -> Result<()> {
    if options.frames == 0 {
        return Err(Error::bad_input("--preset animations needs at least one measured frame"));
    }
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    for row in rows {
        let blades = row.scene.blades();
        let responses = row.responses(responses);
        for &(mode, field) in &responses {
            let animation = animation(mode, row.culled, field);
            let culling = (row.culled, Default::default(), false);
            crate::app::check_scene(device, blades, row.segments, options.size, &animation, false, culling)?;
        }
        let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
        let one = crate::render::scene_gpu::SceneGpu::memory_bytes(u64::from(blades), u64::from(cells));
        let all = responses.len() as u64 * one + crate::app::frame_target_bytes(extent, &Default::default(), false);
        let what = format!("--preset animations: {} ({} renderers)", row.label, responses.len());
        device.check_budget(all, &what)?;
    }
    Ok(())
}

/// One row: a renderer per response, measured interleaved.
fn measure_row(
    device: &Arc<Device>,
    row: &Row,
    responses: &[(Mode, FieldKind)],
    target: &mut OffscreenTarget,
    options: &AnimationsBenchOptions,
    frames: &mut Progress,
) -> Result<AnimationsRow> {
    let scene = row.scene.scene();
    let culling = if row.culled { Culling::default_for(row.segments) } else { Culling::brute_force(row.segments) };
    let settings = RenderSettings::offscreen(row.segments, culling);
    let mut renderers = responses
        .iter()
        .map(|&(mode, field)| Renderer::new(device.clone(), &scene, settings, animation(mode, row.culled, field)))
        .collect::<Result<Vec<_>>>()?;
    let camera = scene.default_camera();
    let mut subject = Offscreen {
        renderers: &mut renderers,
        targets: std::slice::from_mut(target),
        camera: &|_, _| camera,
        time: &|round| (f64::from(round) * DT) as f32,
        after: None,
    };
    let measured = measure(&mut subject, Schedule { warmup: options.warmup, frames: options.frames }, frames)?;
    let mut variants = Vec::new();
    for (i, (renderer, &(mode, _))) in renderers.iter().zip(responses).enumerate() {
        let own = renderer.response_passes();
        let frames_ms: Vec<f64> = measured.timings(i).map(|t| t.gpu_ms).collect();
        let response_ms: Vec<f64> = measured
            .timings(i)
            .map(|t| t.passes.iter().filter(|p| own.contains(&p.name)).fold(0.0, |sum, p| sum + p.ms))
            .collect();
        let steps_per_frame = 1;
        let response = Summary::of(&response_ms);
        variants.push(AnimationsVariant {
            animation: animation_name(mode).into(),
            response: renderer.response_name().into(),
            wind_field: renderer.wind_field_name().into(),
            gpu_ms: Summary::of(&frames_ms),
            frames_ms,
            ratio_to_static: 0.0,
            passes: own.iter().map(|p| p.to_string()).collect(),
            ms_per_step: response.median / f64::from(steps_per_frame),
            response_ms: response,
            steps_per_frame,
        });
    }
    let base = variants[0].gpu_ms.median;
    for v in &mut variants {
        v.ratio_to_static = if base > 0.0 { v.gpu_ms.median / base } else { 0.0 };
    }
    Ok(AnimationsRow {
        label: row.label.clone(),
        culled: row.culled,
        blades: row.scene.blades(),
        segments: row.segments,
        wind_field: row.field.name().into(),
        variants,
    })
}
