//! `meadow bench --preset msaa`: what multisampling costs and what it buys, side by side in one
//! run. Per row (the viewer's default scene, 100 000 stored blades through the cull with the
//! outline as geometry; and brute force, where every blade's outline is alpha-tested), three
//! variants render the same scene: no MSAA, N× with alpha to coverage, N× with the alpha test
//! (N the largest supported count up to 4).
//!
//! - **Cost**: the default camera, interleaved (A B C A B C …), warm-up frames discarded: median
//!   GPU ms and the ratio to no MSAA.
//! - **Temporal stability**: a slow pan (the yaw grows by [`PAN_DEG_PER_FRAME`] a frame) with the
//!   wind frozen (every frame at the same simulation time): the mean over consecutive frames of
//!   the 8×8-filtered frame-to-frame change ([`box_filtered_difference`]), and its ratio to no
//!   MSAA. Detail that shimmers as the camera moves changes blocks; content that moves by a
//!   fraction of a pixel barely does.
//!
//! Results go to `msaa.json`, `msaa.csv` and `msaa-far-field.png` ([`report`]).

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::harness::document::{Header, Summary};
use crate::harness::measure::{measure, Offscreen, Schedule};
use crate::harness::Progress;
use crate::imagediff::box_filtered_difference;
use crate::render::animation::AnimationSettings;
use crate::render::culling::Culling;
use crate::render::msaa::{self, Msaa};
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

pub mod document;
mod report;

pub use document::{MsaaDocument, MsaaOptionsRecord, MsaaRow, MsaaVariant};
pub use report::{csv, table, write, FILES};

/// Side in pixels of the blocks frames are averaged over before they are compared.
pub const DIFF_BLOCK: u32 = 8;
/// How far the pan turns the camera each frame, in degrees (about 0.7 px at 1280×720).
pub const PAN_DEG_PER_FRAME: f32 = 0.05;
/// Simulation time of every frame: the wind is frozen.
pub const SIMULATION_TIME: f32 = 0.0;
/// Segments of the blades.
pub const SEGMENTS: u32 = 4;

/// The options of a run.
#[derive(Clone, Debug)]
pub struct MsaaBenchOptions {
    /// Blades of the stored field.
    pub blades: u32,
    /// Picture size.
    pub size: (u32, u32),
    /// Frames per variant discarded before the cost is measured.
    pub warmup: u32,
    /// Frames per variant measured for the cost.
    pub frames: u32,
    /// Frames per variant of the pan (frame-to-frame changes: one fewer).
    pub pan_frames: u32,
    /// Output directory.
    pub out: PathBuf,
}

impl MsaaBenchOptions {
    /// The preset: the viewer's default scene at 1280×720.
    pub fn preset(out: PathBuf) -> Self {
        Self { blades: 100_000, size: (1280, 720), warmup: 2, frames: 6, pan_frames: 12, out }
    }
}

/// A row: its label and how its blades are drawn.
const ROWS: [(&str, bool); 2] = [("default (cull, outline as geometry)", true), ("brute force (alpha-tested)", false)];

/// The variants at `samples` samples: (name, MSAA settings).
fn variants(samples: u32) -> [(String, Msaa); 3] {
    [
        ("no MSAA".into(), Msaa { samples: 1, alpha_to_coverage: false }),
        (format!("{samples}x alpha to coverage"), Msaa { samples, alpha_to_coverage: true }),
        (format!("{samples}x alpha test"), Msaa { samples, alpha_to_coverage: false }),
    ]
}

/// What a run measured: the document, and per row the last pan frame of each variant (RGB8, for
/// the far-field crop).
pub struct MsaaRun {
    /// The document (`msaa.json`).
    pub doc: MsaaDocument,
    /// Per row, per variant, the last pan picture.
    pub pictures: Vec<Vec<Vec<u8>>>,
}

/// Run the benchmark; `progress(done, total)` after every frame.
pub fn run(device: &Arc<Device>, options: &MsaaBenchOptions, mut progress: impl FnMut(u64, u64)) -> Result<MsaaRun> {
    let samples = msaa::supported_counts(device).into_iter().filter(|&n| n <= 4).max().unwrap_or(1);
    if samples == 1 {
        return Err(Error::bad_input(format!("--preset msaa: {} supports no multisampling", device.info.name)));
    }
    if options.size.0 < 8 * DIFF_BLOCK || options.size.1 < 8 * DIFF_BLOCK {
        return Err(Error::bad_input(format!(
            "--size {}x{}: --preset msaa needs at least {}x{} pixels",
            options.size.0,
            options.size.1,
            8 * DIFF_BLOCK,
            8 * DIFF_BLOCK
        )));
    }
    check(device, options, samples)?;
    let extent = vk::Extent2D { width: options.size.0, height: options.size.1 };
    let per_variant = u64::from(options.warmup + options.frames + options.pan_frames);
    let mut frames = Progress::new(ROWS.len() as u64 * 3 * per_variant, &mut progress);
    let scene = Scene::generate(options.blades, 1);
    let mut targets = Vec::new();
    let measured = (|| {
        for _ in 0..3 {
            targets.push(OffscreenTarget::new(device, extent)?);
        }
        let mut rows = Vec::new();
        for (label, culled) in ROWS {
            rows.push(measure_row(device, &scene, (label, culled), samples, &mut targets, options, &mut frames)?);
        }
        Ok::<_, Error>(rows)
    })();
    for target in targets {
        // SAFETY: measure_row dropped its renderers, which waited for their frames.
        unsafe { target.destroy(device) };
    }
    let (rows, pictures): (Vec<MsaaRow>, Vec<Vec<Vec<u8>>>) = measured?.into_iter().unzip();
    let recorded = MsaaOptionsRecord {
        blades: options.blades,
        segments: SEGMENTS,
        size: [options.size.0, options.size.1],
        warmup: options.warmup,
        frames: options.frames,
        pan_frames: options.pan_frames,
        pan_deg_per_frame: f64::from(PAN_DEG_PER_FRAME),
        simulation_time_s: f64::from(SIMULATION_TIME),
        diff_block: DIFF_BLOCK,
        samples,
    };
    let doc = MsaaDocument { header: Header::new(device, "msaa", options.size), options: recorded, rows };
    Ok(MsaaRun { doc, pictures })
}

/// Every check of the run against the device before anything is built: each row's scene at each
/// variant (`app::check_scene`: limits, multisampled images), then what a row holds at once
/// (three renderers, each with its target and multisampled pair) against the memory budget.
fn check(device: &Device, options: &MsaaBenchOptions, samples: u32) -> Result<()> {
    let (blades, size) = (options.blades, options.size);
    for (_, culled) in ROWS {
        for (_, msaa) in variants(samples) {
            let animation = AnimationSettings::default();
            crate::app::check_scene(device, blades, SEGMENTS, size, &animation, false, (culled, msaa, false))?;
        }
    }
    let extent = vk::Extent2D { width: size.0, height: size.1 };
    let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
    let scene = crate::render::scene_gpu::SceneGpu::memory_bytes(u64::from(blades), u64::from(cells));
    let row: u64 =
        variants(samples).iter().map(|(_, msaa)| scene + crate::app::frame_target_bytes(extent, msaa, false)).sum();
    device.check_budget(row, &format!("--preset msaa with {blades} blades at {}x{} (three renderers)", size.0, size.1))
}

/// A target's picture as RGB8.
fn rgb(target: &OffscreenTarget) -> Vec<u8> {
    target.pixels().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// One row: its three renderers built, the cost measured interleaved, then the pan. Returns the
/// row and each variant's last pan picture.
fn measure_row(
    device: &Arc<Device>,
    scene: &Scene,
    (label, culled): (&str, bool),
    samples: u32,
    targets: &mut [OffscreenTarget],
    options: &MsaaBenchOptions,
    frames: &mut Progress,
) -> Result<(MsaaRow, Vec<Vec<u8>>)> {
    let culling = if culled { Culling::default_for(SEGMENTS) } else { Culling::brute_force(SEGMENTS) };
    let variants = variants(samples);
    let mut renderers = variants
        .iter()
        .map(|(_, msaa)| {
            let settings = RenderSettings { msaa: *msaa, ..RenderSettings::offscreen(SEGMENTS, culling) };
            Renderer::new(device.clone(), scene, settings, AnimationSettings::default())
        })
        .collect::<Result<Vec<_>>>()?;
    let camera = scene.default_camera();
    let mut cost = Offscreen {
        renderers: &mut renderers,
        targets: &mut *targets,
        camera: &|_, _| camera,
        time: &|_| SIMULATION_TIME,
        after: None,
    };
    let measured = measure(&mut cost, Schedule { warmup: options.warmup, frames: options.frames }, frames)?;
    let gpu_ms: Vec<Vec<f64>> = (0..variants.len()).map(|i| measured.timings(i).map(|t| t.gpu_ms).collect()).collect();
    let (changes, last) = pan(&mut renderers, targets, camera, options, frames)?;
    let median = |ms: &[f64]| Summary::of(ms).median;
    let mean = |c: &[f64]| c.iter().sum::<f64>() / c.len().max(1) as f64;
    let (cost_off, change_off) = (median(&gpu_ms[0]), mean(&changes[0]));
    let entries: Vec<MsaaVariant> = variants
        .iter()
        .zip(gpu_ms.into_iter().zip(changes))
        .map(|((name, m), (gpu_ms, changes))| MsaaVariant {
            variant: name.clone(),
            samples: m.samples,
            alpha_to_coverage: m.enabled() && m.alpha_to_coverage,
            gpu_ms: Summary::of(&gpu_ms),
            cost_ratio: if cost_off > 0.0 { median(&gpu_ms) / cost_off } else { 0.0 },
            frames_ms: gpu_ms,
            change_percent: mean(&changes),
            change_ratio: if change_off > 0.0 { mean(&changes) / change_off } else { 0.0 },
            changes_percent: changes,
        })
        .collect();
    Ok((MsaaRow { label: label.into(), culled, blades: scene.blades.len(), variants: entries }, last))
}

/// What a pan measured: per variant, its frame-to-frame changes (%) and its last picture (RGB8).
type Pan = (Vec<Vec<f64>>, Vec<Vec<u8>>);

/// The pan, through the measuring loop without warm-up: every variant renders each pan frame in
/// turn; per variant, the 8×8-filtered mean change between consecutive frames, in % of full
/// scale, and its last picture. Its frame times are not kept.
fn pan(
    renderers: &mut [Renderer],
    targets: &mut [OffscreenTarget],
    start: Camera,
    options: &MsaaBenchOptions,
    frames: &mut Progress,
) -> Result<Pan> {
    let (w, h) = options.size;
    let mut previous: Vec<Option<Vec<u8>>> = vec![None; renderers.len()];
    let mut changes = vec![Vec::new(); renderers.len()];
    let mut compare = |i: usize, _: &crate::render::Renderer, target: &OffscreenTarget| {
        let picture = rgb(target);
        if let Some(before) = &previous[i] {
            changes[i].push(box_filtered_difference(before, &picture, w, h, DIFF_BLOCK).mean_percent);
        }
        previous[i] = Some(picture);
    };
    let mut subject = Offscreen {
        renderers,
        targets,
        camera: &|_, k| Camera { yaw_deg: start.yaw_deg + k as f32 * PAN_DEG_PER_FRAME, ..start },
        time: &|_| SIMULATION_TIME,
        after: Some(&mut compare),
    };
    measure(&mut subject, Schedule { warmup: 0, frames: options.pan_frames }, frames)?;
    Ok((changes, previous.into_iter().map(Option::unwrap_or_default).collect()))
}
