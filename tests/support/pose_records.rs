//! What the blade-response tests that read pose records back share (`tests/verlet.rs`,
//! `tests/inertial.rs`, `tests/virtual_inertial.rs`): a brute-force run that reads the records
//! and the corners' wind after every frame, the records decoded into backbones, the neutral
//! backbone, a swing's period and peaks, and a thousand frames through the cull. Included with
//! `#[path]` next to `mod support;`.

#![allow(dead_code)] // each test crate that includes it uses a different subset

use std::sync::Arc;

use ash::vk;
use glam::{Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::clock::StepClock;
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::{Device, DeviceSelector};
use meadow::wind::{GlobalWind, Wind};

/// Segments the records are read at.
pub const SEGMENTS: u32 = 8;

/// A steady global wind towards `direction_deg` of `strength` keyframe units (× 8 m/s).
pub fn wind(direction_deg: f32, strength: f32) -> Wind {
    Wind { global: Some(GlobalWind { direction_deg, strength, gusts: false }), ..Default::default() }
}

/// What a run read back after each frame: the records, and the wind at the corners.
pub struct Frame {
    pub records: Vec<u32>,
    pub corners: Vec<Vec4>,
}

/// Render `winds.len()` frames of `scene` by brute force, frame k at step k under `winds[k]`
/// (the first frame starts every blade at its equilibrium under `winds[0]`).
/// `animation`'s clock is set to `dt`.
pub fn run(
    scene: &Scene,
    animation: AnimationSettings,
    dt: f64,
    winds: &[Wind],
) -> (Vec<Frame>, meadow::scene::clusters::ClusterGrid) {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(crate::support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, Culling::brute_force(SEGMENTS));
        let animation = AnimationSettings { clock: StepClock { dt }, ..animation };
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
        let camera = Camera::default_for(&scene.terrain);
        let mut frames = Vec::new();
        for (k, w) in winds.iter().enumerate() {
            *renderer.wind_mut() = w.clone();
            // Half a step in: an f32 time at step k exactly could round to the step before.
            renderer.render_offscreen(&mut target, &camera, ((k as f64 + 0.5) * dt) as f32)?;
            let records = renderer.read_pose_records()?;
            let corners = renderer.read_wind_corners(0)?.into_iter().map(Vec4::from).collect();
            frames.push(Frame { records, corners });
        }
        let grid = renderer.cluster_grid();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok((frames, grid))
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Level `level` of blade `blade`'s record, in metres in the blade's frame.
pub fn level(records: &[u32], blade: usize, level: u32, height: f32) -> Vec3 {
    meadow::render::animation::poses::recorded_point(records, (blade, level), SEGMENTS, height)
}

/// The drawn backbone of blade `blade`: its levels, in the world's axes relative to the root.
pub fn backbone(records: &[u32], scene: &Scene, blade: usize) -> Vec<Vec3> {
    let b = &scene.blades[blade];
    let (across, normal) = bezier::frame(b);
    (0..=SEGMENTS)
        .map(|m| {
            let l = level(records, blade, m, b.height);
            across * l.x + Vec3::Y * l.y + normal * l.z
        })
        .collect()
}

pub fn polyline_length(points: &[Vec3]) -> f32 {
    points.windows(2).map(|p| (p[1] - p[0]).length()).sum()
}

/// The neutral backbone of `blade` (world axes, relative to the root) at the levels.
pub fn neutral(scene: &Scene, blade: usize) -> Vec<Vec3> {
    let b = &scene.blades[blade];
    let (across, normal) = bezier::frame(b);
    let p = bezier::neutral_control_points(b);
    (0..=SEGMENTS)
        .map(|m| {
            let l = bezier::point(&p, m as f32 / SEGMENTS as f32);
            across * l.x + Vec3::Y * l.y + normal * l.z
        })
        .collect()
}

/// The period of a swing about 0 (from its first and last upward zero crossings, in seconds) and
/// the magnitudes of its successive peaks.
pub fn swing(trace: &[f32], dt: f64) -> (f32, Vec<f32>) {
    let crossings: Vec<f32> = trace
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(k, w)| k as f32 + w[0] / (w[0] - w[1]))
        .collect();
    assert!(crossings.len() >= 2, "no swing: {trace:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f32 * dt as f32;
    let mut peaks = Vec::new();
    let mut best = 0.0f32;
    for w in trace.windows(2) {
        best = best.max(w[0].abs());
        if (w[0] < 0.0) != (w[1] < 0.0) {
            peaks.push(best);
            best = 0.0;
        }
    }
    (period, peaks)
}

/// Render a thousand frames of `mode` through the cull on a block field, the camera across blocks
/// and back and looking at the sky now and then (a store scrolls, blades are culled and reset):
/// the allocated bytes and pending deletions at frames 100 and 1000, which must be equal.
pub fn thousand_frames_through_the_cull(device: &Arc<Device>, mode: Mode) -> meadow::Result<Vec<(u64, usize)>> {
    let scene = Scene::blocks(FieldSpec { size: None, density: 150.0 }, 3);
    let settings = RenderSettings::offscreen(4, Culling::default_for(4));
    let animation = AnimationSettings { mode, ..Default::default() };
    let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
    let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
    let start = scene.default_camera();
    let mut samples = Vec::new();
    for step in 0..1000u64 {
        let x = start.position.x + 6.0 * ((step / 9) % 2) as f32;
        let pitch = if step % 50 == 49 { 80.0 } else { start.pitch_deg };
        let camera = Camera { position: Vec3::new(x, start.position.y, start.position.z), pitch_deg: pitch, ..start };
        renderer.render_offscreen(&mut target, &camera, step as f32 / 60.0)?;
        if step == 100 || step == 999 {
            let bytes = device.allocator().generate_report().total_allocated_bytes;
            samples.push((bytes, renderer.pending_deletions()));
        }
    }
    drop(renderer);
    // SAFETY: render_offscreen waited for its frame; the renderer is gone.
    unsafe { target.destroy(device) };
    Ok(samples)
}

/// [`thousand_frames_through_the_cull`] on a device of its own, validated: the two samples.
pub fn memory_through_the_cull(mode: Mode) -> Vec<(u64, usize)> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(crate::support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| thousand_frames_through_the_cull(device, mode));
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}
