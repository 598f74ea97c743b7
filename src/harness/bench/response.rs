//! `meadow bench --preset response`: how each blade response answers a step gust (issue "The
//! companion blade models"). A field of `BLADES` stored blades, drawn by brute force so that every
//! blade keeps its pose record by its stored index (its stable id), rests under no wind until
//! `GUST_AT`, then a steady wind of `WIND_MS` towards +x blows until `DURATION`, one step a frame.
//! After every frame the pose records are read back, and the tip of each of the `TRACKED` blades
//! gives its displacement downwind from its rest. `response.json` holds the traces and each
//! model's natural period (the chains' and Verlet's spring, 2π/√k; none for the stateless
//! responses, which follow the wind at once), `response.png` plots them, one panel per response,
//! the natural period marked after the gust.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::harness::document::{to_json, Header};
use crate::harness::plot::{line_panels, Panel, Scale, Series};
use crate::render::animation::clock::StepClock;
use crate::render::animation::poses::recorded_point;
use crate::render::animation::sine::SinePhase;
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::culling::Culling;
use crate::render::{OffscreenTarget, RenderSettings, Renderer};
use crate::scene::{bezier, Camera, Scene};
use crate::vk::Device;
use crate::wind::{GlobalWind, Wind, KEYFRAME_WIND_SCALE};

/// Blades of the field.
pub const BLADES: u32 = 2000;
/// Segments of the records.
pub const SEGMENTS: u32 = 8;
/// The fixed step (`--dt`'s default), one a frame.
pub const DT: f64 = 1.0 / 60.0;
/// When the gust starts, seconds.
pub const GUST_AT: f64 = 0.5;
/// How long the run lasts, seconds.
pub const DURATION: f64 = 3.0;
/// The gust's strength in keyframe units (× `KEYFRAME_WIND_SCALE` m/s).
pub const STRENGTH: f32 = 0.5;
/// The stored blades traced.
pub const TRACKED: [u32; 3] = [0, 700, 1400];
/// The files of a run.
pub const FILES: [&str; 2] = ["response.json", "response.png"];

/// The options of a run.
#[derive(Clone, Debug)]
pub struct ResponseBenchOptions {
    /// The responses, in order (the static blades do not move: they are left out).
    pub animations: Vec<Mode>,
    /// Output directory.
    pub out: PathBuf,
}

impl ResponseBenchOptions {
    /// Every response that moves.
    pub fn preset(out: PathBuf) -> Self {
        let sine = |p| Mode::Sine(p);
        let animations = vec![
            Mode::Texture,
            sine(SinePhase::Object),
            sine(SinePhase::Vertex),
            sine(SinePhase::Cluster),
            Mode::Verlet,
            Mode::Inertial,
            Mode::VirtualInertial,
        ];
        Self { animations, out }
    }
}

/// A `response.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResponseDocument {
    /// The fields every document carries.
    #[serde(flatten)]
    pub header: Header,
    /// The fixed step, seconds.
    pub dt_s: f64,
    /// When the gust starts, seconds.
    pub gust_at_s: f64,
    /// The gust's wind towards +x, m/s.
    pub wind_ms: f32,
    /// Each frame's simulation time, seconds.
    pub times_s: Vec<f64>,
    /// One trace per response.
    pub models: Vec<ResponseModel>,
}

/// A response's traces.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResponseModel {
    /// `--animation`'s value.
    pub animation: String,
    /// `BladeResponse::name`.
    pub response: String,
    /// The spring's period 2π/√k with the default constants (`None`: stateless).
    pub natural_period_s: Option<f64>,
    /// The traced blades.
    pub blades: Vec<TrackedBlade>,
}

/// One blade's tip over time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrackedBlade {
    /// Its stored index.
    pub id: u32,
    /// Its height, metres.
    pub height_m: f32,
    /// Its tip's displacement towards +x from its rest, metres, per frame.
    pub tip_m: Vec<f64>,
}

/// 2π/√k of the response's spring with its default constants, if it has one.
fn natural_period(mode: Mode) -> Option<f64> {
    let k = match mode {
        Mode::Verlet => crate::render::animation::verlet::VerletParams::default().stiffness,
        Mode::Inertial | Mode::VirtualInertial => crate::render::animation::chain::ChainParams::default().stiffness,
        _ => return None,
    };
    Some(std::f64::consts::TAU / f64::from(k).sqrt())
}

/// The wind of frame time `t`: calm, then the gust.
fn wind_at(t: f64) -> Wind {
    let strength = if t >= GUST_AT { STRENGTH } else { 0.0 };
    Wind { global: Some(GlobalWind { direction_deg: 0.0, strength, gusts: false }), ..Default::default() }
}

/// Refuse what cannot be traced: the static blades do not move.
pub fn check(options: &ResponseBenchOptions) -> Result<()> {
    match options.animations.contains(&Mode::Static) {
        true => Err(Error::bad_input("--preset response traces moving blades: drop static from --animations")),
        false => Ok(()),
    }
}

/// Run every response through the gust; `progress(done, total)` after every frame.
pub fn run(
    device: &Arc<Device>,
    options: &ResponseBenchOptions,
    mut progress: impl FnMut(u64, u64),
) -> Result<ResponseDocument> {
    check(options)?;
    let frames = (DURATION / DT).round() as u64;
    let times_s: Vec<f64> = (0..frames).map(|k| (k as f64 + 0.5) * DT).collect();
    let scene = Scene::generate(BLADES, 1);
    let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
    let total = frames * options.animations.len() as u64;
    let mut models = Vec::new();
    let mut result = Ok(());
    for (i, &mode) in options.animations.iter().enumerate() {
        let done = i as u64 * frames;
        match trace(device, &scene, mode, (&mut target, &times_s), &mut |k| progress(done + k, total)) {
            Ok(model) => models.push(model),
            Err(e) => {
                result = Err(e);
                break;
            }
        }
    }
    // SAFETY: each renderer waited for its frames when dropped.
    unsafe { target.destroy(device) };
    result?;
    Ok(ResponseDocument {
        header: Header::new(device, "response", (64, 36)),
        dt_s: DT,
        gust_at_s: GUST_AT,
        wind_ms: STRENGTH * KEYFRAME_WIND_SCALE,
        times_s,
        models,
    })
}

/// One response's traces: a renderer, a frame per time, the tracked tips read back after each.
fn trace(
    device: &Arc<Device>,
    scene: &Scene,
    mode: Mode,
    (target, times): (&mut OffscreenTarget, &[f64]),
    progress: &mut dyn FnMut(u64),
) -> Result<ResponseModel> {
    let settings = RenderSettings::offscreen(SEGMENTS, Culling::brute_force(SEGMENTS));
    let animation = AnimationSettings {
        mode,
        eval: Eval::Blade,
        clock: StepClock { dt: DT },
        wind: wind_at(0.0),
        ..Default::default()
    };
    let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
    let camera = Camera::default_for(&scene.terrain);
    let mut tips: Vec<Vec<f64>> = vec![Vec::new(); TRACKED.len()];
    for (k, &t) in times.iter().enumerate() {
        *renderer.wind_mut() = wind_at(t);
        renderer.render_offscreen(target, &camera, t as f32)?;
        let records = renderer.read_pose_records()?;
        for (trace, &id) in tips.iter_mut().zip(&TRACKED) {
            let blade = &scene.blades[id as usize];
            let (across, normal) = bezier::frame(blade);
            let tip = recorded_point(&records, (id as usize, SEGMENTS), SEGMENTS, blade.height);
            trace.push(f64::from((across * tip.x + normal * tip.z).x));
        }
        progress(k as u64 + 1);
    }
    let blades = TRACKED
        .iter()
        .zip(tips)
        .map(|(&id, tip)| {
            // From the rest the first frame holds (no wind until the gust).
            let rest = tip[0];
            TrackedBlade {
                id,
                height_m: scene.blades[id as usize].height,
                tip_m: tip.iter().map(|x| x - rest).collect(),
            }
        })
        .collect();
    Ok(ResponseModel {
        animation: crate::harness::bench::animations::animation_name(mode).into(),
        response: renderer.response_name().into(),
        natural_period_s: natural_period(mode),
        blades,
    })
}

/// `response.json` and `response.png` into `dir`.
pub fn write(doc: &ResponseDocument, dir: &Path) -> Result<()> {
    let [json, png] = FILES;
    crate::app::write_text(&dir.join(json), &to_json(doc))?;
    chart(doc, &dir.join(png))
}

/// One panel per response: its blades' tips over time, and the natural period after the gust as
/// a vertical mark.
fn chart(doc: &ResponseDocument, path: &Path) -> Result<()> {
    let panels: Vec<Panel> = doc
        .models
        .iter()
        .map(|m| {
            let mut series: Vec<Series> = m
                .blades
                .iter()
                .map(|b| Series {
                    label: format!("blade {} ({:.2} m)", b.id, b.height_m),
                    points: doc.times_s.iter().zip(&b.tip_m).step_by(2).map(|(&t, &x)| (t, x)).collect(),
                })
                .collect();
            let top = m.blades.iter().flat_map(|b| b.tip_m.iter().copied()).fold(0.0, f64::max);
            if let Some(period) = m.natural_period_s {
                let at = doc.gust_at_s + period;
                series.push(Series {
                    label: format!("gust + 2π/√k = {period:.3} s"),
                    points: vec![(at, 0.0), (at, top)],
                });
            }
            let title = match m.natural_period_s {
                Some(_) => m.response.clone(),
                None => format!("{} (stateless)", m.response),
            };
            Panel {
                title,
                x_label: "time (s)".into(),
                y_label: "tip downwind (m)".into(),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                series,
            }
        })
        .collect();
    let columns = panels.len().min(3);
    let rows = panels.len().div_ceil(columns.max(1)) as u32;
    let title = format!("A step gust of {} m/s towards +x at {} s", doc.wind_ms, doc.gust_at_s);
    line_panels(path, (500 * columns as u32, 360 * rows), &title, &panels, columns)
}

/// The table printed after a run: per response, the largest tip displacement, when it came, and
/// where the tip settled (the last frame), mean over the traced blades.
pub fn table(doc: &ResponseDocument) -> String {
    let mut out =
        format!("{:<24} {:>10} {:>10} {:>10} {:>12}\n", "response", "peak (m)", "at (s)", "end (m)", "period (s)");
    for m in &doc.models {
        let n = m.blades.len().max(1) as f64;
        let peak_of = |b: &TrackedBlade| {
            b.tip_m.iter().copied().enumerate().fold((0, f64::MIN), |a, (i, x)| if x > a.1 { (i, x) } else { a })
        };
        let peak = m.blades.iter().map(|b| peak_of(b).1).sum::<f64>() / n;
        let at = m.blades.iter().map(|b| doc.times_s[peak_of(b).0]).sum::<f64>() / n;
        let end = m.blades.iter().map(|b| *b.tip_m.last().unwrap_or(&0.0)).sum::<f64>() / n;
        let period = m.natural_period_s.map_or("-".to_string(), |p| format!("{p:.3}"));
        out.push_str(&format!("{:<24} {:>10.4} {:>10.3} {:>10.4} {:>12}\n", m.response, peak, at, end, period));
    }
    out
}
