//! Benchmarks of pairs side by side (`--preset landscape`, `plants`, `interaction`): renderers of a few
//! scenes render in turn (A B C D … A B …, warm-up rounds discarded), each pair a reference and a
//! subject whose median GPU frame is measured against it, with their last pictures compared.

use std::path::PathBuf;
use std::sync::Arc;

use ash::vk;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::harness::document::{ClassDrawn, Summary};
use crate::harness::measure::{measure, Measured, Offscreen, Schedule};
use crate::harness::Progress;
use crate::imagediff::compare_rgb;
use crate::render::animation::AnimationSettings;
use crate::render::culling::Culling;
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{Camera, Scene};
use crate::vk::Device;

/// Segments of the blades.
pub const SEGMENTS: u32 = 4;

/// The options of a run.
#[derive(Clone, Debug)]
pub struct PairBenchOptions {
    /// Picture size.
    pub size: (u32, u32),
    /// Rounds discarded first.
    pub warmup: u32,
    /// Rounds measured.
    pub frames: u32,
    /// Output directory.
    pub out: PathBuf,
}

impl PairBenchOptions {
    /// The presets': 1280×720, 2 + 10 rounds.
    pub fn preset(out: PathBuf) -> Self {
        Self { size: (1280, 720), warmup: 2, frames: 10, out }
    }
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
    /// Entries drawn in the last frame, every class.
    pub drawn: u64,
    /// Per draw class, the blades first, what it drew in the last frame.
    #[serde(default)]
    pub classes: Vec<ClassDrawn>,
    /// With colliders, the blades holding an interaction patch's state after the last frame
    /// (`render::animation::patches`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub patches: Option<u64>,
}

/// A pair: its label, its reference's and subject's names, and the bound on their ratio.
pub type PairSpec = (&'static str, &'static str, &'static str, f64);

/// How the scenes of a run are animated: each scene's animation (one for all, or one each), and
/// the simulation time of round r, `start + r · step` seconds.
pub(crate) struct Animated<'a> {
    pub animations: &'a [AnimationSettings],
    pub start: f32,
    pub step: f32,
    /// Each scene's render settings (one for all, or one each); empty: `default_settings`.
    pub settings: &'a [RenderSettings],
}

impl<'a> Animated<'a> {
    /// Every scene animated by `animation`, at t = 0.
    pub fn still(animation: &'a AnimationSettings) -> Self {
        Self { animations: std::slice::from_ref(animation), start: 0.0, step: 0.0, settings: &[] }
    }

    fn of(&self, scene: usize) -> &AnimationSettings {
        &self.animations[scene.min(self.animations.len() - 1)]
    }

    fn settings_of(&self, scene: usize) -> RenderSettings {
        match self.settings.len() {
            0 => default_settings(),
            n => self.settings[scene.min(n - 1)],
        }
    }
}

/// The presets' render settings: the cull and LOD on, pipeline statistics counted.
pub(crate) fn default_settings() -> RenderSettings {
    RenderSettings { pipeline_statistics: true, ..RenderSettings::offscreen(SEGMENTS, Culling::default_for(SEGMENTS)) }
}

/// Measure `specs`' pairs: scenes `2p` (reference) and `2p + 1` (subject) of `scenes` from
/// `cameras`, animated as `animated` says, `schedule`'s rounds of `size` pictures;
/// `progress(done, total)` after every frame.
pub(crate) fn run(
    device: &Arc<Device>,
    (specs, scenes, cameras, animated): (&[PairSpec], &[Scene], &[Camera], Animated),
    size: (u32, u32),
    schedule: Schedule,
    progress: impl FnMut(u64, u64),
) -> Result<Vec<Pair>> {
    let (measured, pictures, patches) = render(device, (scenes, cameras, animated), size, schedule, progress)?;
    let variant = |i: usize| {
        let gpu: Vec<f64> = measured.timings(i).map(|t| t.gpu_ms).collect();
        let cull = measured.all(i).last().and_then(|f| f.timings.cull);
        let c = cameras[i];
        let name = [specs[i / 2].1, specs[i / 2].2][i % 2].to_string();
        let camera = [c.position.x, c.position.y, c.position.z, c.yaw_deg, c.pitch_deg];
        let (drawn, classes) = cull.map_or((0, Vec::new()), |c| (c.total_drawn(), ClassDrawn::of(&c)));
        Variant { name, camera, gpu_ms: Summary::of(&gpu), drawn, classes, patches: patches[i] }
    };
    Ok(specs
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
        .collect())
}

/// What `render` measured: every frame's timings, each variant's last picture (RGB8), and with
/// colliders the blades holding a patch after its last frame.
type Rendered = (Measured, Vec<Vec<u8>>, Vec<Option<u64>>);

/// Render `scenes` from their `cameras` in turn, `schedule`'s rounds of `size` pictures: every
/// frame's timings, each variant's last picture (RGB8), and with colliders the blades holding a
/// patch after its last frame.
fn render(
    device: &Arc<Device>,
    (scenes, cameras, animated): (&[Scene], &[Camera], Animated),
    size: (u32, u32),
    schedule: Schedule,
    mut progress: impl FnMut(u64, u64),
) -> Result<Rendered> {
    let mut renderers = Vec::new();
    for (i, scene) in scenes.iter().enumerate() {
        renderers.push(Renderer::new(device.clone(), scene, animated.settings_of(i), animated.of(i).clone())?);
    }
    let n = scenes.len();
    let mut targets = vec![OffscreenTarget::new(device, vk::Extent2D { width: size.0, height: size.1 })?];
    let mut frames = Progress::new(n as u64 * u64::from(schedule.rounds()), &mut progress);
    let mut pictures: Vec<Vec<u8>> = vec![Vec::new(); n];
    let mut patches: Vec<Option<u64>> = vec![None; n];
    let mut failed = None;
    let last = schedule.rounds() - 1;
    let mut round_of = vec![0u32; n];
    let measured = {
        let time = |round: u32| animated.start + animated.step * round as f32;
        let mut after = |i: usize, renderer: &Renderer, target: &OffscreenTarget| {
            if round_of[i] == last {
                pictures[i] = target.pixels().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
                let step = renderer.animation().clock.steps_to(f64::from(time(last)));
                match crate::app::patch_counts(renderer, step) {
                    Ok(counts) => patches[i] = counts.map(|(_, live)| live),
                    Err(e) => failed = Some(e),
                }
            }
            round_of[i] += 1;
        };
        let camera = |i: usize, _| cameras[i];
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
    if let Some(e) = failed {
        return Err(e);
    }
    Ok((measured?, pictures, patches))
}

/// `pairs` as rows of a text table, after its header line.
pub fn table_rows(pairs: &[Pair]) -> String {
    let mut out = String::from(
        "pair | reference ms | subject ms | ratio (target) | drawn | pixels within ±3, largest difference\n",
    );
    for p in pairs {
        let met = if p.within_target { "met" } else { "missed" };
        let classes = |v: &Variant| match v.classes.len() {
            0 | 1 => v.drawn.to_string(),
            _ => v.classes.iter().map(|c| format!("{} {}", c.drawn, c.class)).collect::<Vec<_>>().join(" + "),
        };
        out.push_str(&format!(
            "{} | {:.1} | {:.1} | {:.3}x (<= {}, {met}) | {} / {} | {:.3} %, {}\n",
            p.label,
            p.reference.gpu_ms.median,
            p.subject.gpu_ms.median,
            p.ratio,
            p.target,
            classes(&p.reference),
            classes(&p.subject),
            100.0 * p.within_3,
            p.max_diff
        ));
    }
    out
}
