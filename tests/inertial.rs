//! Belyaev's inertial blades (§3.1; `render::animation::chain`, `render::animation::inertial`),
//! read back from the GPU: the pose records `shaders/animation/inertial.comp` wrote, frame by
//! frame, one step a frame, on a stored field by brute force (records by stored blade; the CPU
//! writes the cluster corners, through the analytic wind field, whose wind the test sets between
//! frames).
//!
//! - Under no wind a blade rests at its neutral shape.
//! - Under a wind towards +x the tips move towards +x, and the drawn backbone keeps its length
//!   within 1 % under the strongest wind.
//! - A released blade swings back: its oscillation decays, its period is within 10 % of a joint's
//!   2π/√(k/J), and it follows the CPU mirror of the same discrete update (`Chain`) step by step.
//! - At the longest step (1/15 s) and the stiffest, most damped constants, under a wind that
//!   reverses, nothing blows up.
//! - A thousand frames through the cull on a block field (the store scrolling, blades culled and
//!   reset) leave the allocated memory flat.

mod support;

use ash::vk;
use glam::{Vec2, Vec3, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::chain::{Chain, ChainParams, ChainState};
use meadow::render::animation::clock::StepClock;
use meadow::render::animation::{self, AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, GlobalWind, Wind, KEYFRAME_WIND_SCALE};

const SEGMENTS: u32 = 8;
const POSE_SCALE: f32 = 2.0; // bindings.glsl

/// A steady global wind towards `direction_deg` of `strength` keyframe units (× 8 m/s).
fn wind(direction_deg: f32, strength: f32) -> Wind {
    Wind { global: Some(GlobalWind { direction_deg, strength, gusts: false }), ..Default::default() }
}

/// What a run read back after each frame: the records, and the wind at the corners.
struct Frame {
    records: Vec<u32>,
    corners: Vec<Vec4>,
}

/// Render `winds.len()` frames of `scene` by brute force, frame k at step k under `winds[k]`
/// (the first frame starts every blade at its equilibrium under `winds[0]`).
fn run(
    scene: &Scene,
    params: ChainParams,
    dt: f64,
    winds: &[Wind],
) -> (Vec<Frame>, meadow::scene::clusters::ClusterGrid) {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(SEGMENTS, Culling::brute_force(SEGMENTS));
        let clock = StepClock { dt };
        let animation = AnimationSettings { mode: Mode::Inertial, chain: params, clock, ..Default::default() };
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
fn level(records: &[u32], blade: usize, level: u32, height: f32) -> Vec3 {
    let at = (blade * (SEGMENTS as usize + 1) + level as usize) * 3;
    let snorm = |bits: u32| (bits as u16 as i16 as f32 / 32767.0).max(-1.0);
    let (w0, w1) = (records[at], records[at + 1]);
    Vec3::new(snorm(w0), snorm(w0 >> 16), snorm(w1)) * (POSE_SCALE * height)
}

/// The drawn backbone of blade `blade`: its levels, in the world's axes relative to the root.
fn backbone(records: &[u32], scene: &Scene, blade: usize) -> Vec<Vec3> {
    let b = &scene.blades[blade];
    let (across, normal) = bezier::frame(b);
    (0..=SEGMENTS)
        .map(|m| {
            let l = level(records, blade, m, b.height);
            across * l.x + Vec3::Y * l.y + normal * l.z
        })
        .collect()
}

fn polyline_length(points: &[Vec3]) -> f32 {
    points.windows(2).map(|p| (p[1] - p[0]).length()).sum()
}

/// The neutral backbone of `blade` (world axes, relative to the root) at the levels.
fn neutral(scene: &Scene, blade: usize) -> Vec<Vec3> {
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

#[test]
fn without_wind_blades_rest_at_their_neutral_shape_and_under_wind_the_tips_go_downwind() {
    let scene = Scene::generate(400, 21);
    let params = ChainParams::default();
    let calm: Vec<Wind> = (0..10).map(|_| wind(0.0, 0.0)).collect();
    let (frames, _) = run(&scene, params, 1.0 / 60.0, &calm);
    for frame in [&frames[0], &frames[9]] {
        for blade in 0..scene.blades.len() {
            let drawn = backbone(&frame.records, &scene, blade);
            let rest = neutral(&scene, blade);
            let h = scene.blades[blade].height;
            for (d, r) in drawn.iter().zip(&rest) {
                assert!((*d - *r).length() < 2e-4 * h, "blade {blade}: {d} against its neutral {r}");
            }
        }
    }
    // 4 m/s for 30 steps, then the strongest wind (16 m/s) for 30.
    let winds: Vec<Wind> = (0..60).map(|k| wind(0.0, if k < 30 { 0.5 } else { 2.0 })).collect();
    let (frames, _) = run(&scene, params, 1.0 / 60.0, &winds);
    for k in [29, 59] {
        for blade in 0..scene.blades.len() {
            let h = scene.blades[blade].height;
            let drawn = backbone(&frames[k].records, &scene, blade);
            let rest = neutral(&scene, blade);
            let moved = drawn[SEGMENTS as usize] - rest[SEGMENTS as usize];
            // A leaning blade also pulls its lean in to keep its length, so some z is expected.
            assert!(moved.x > 0.05 * h && moved.x > moved.z.abs(), "frame {k}, blade {blade}: tip moved {moved}");
            let (l, l0) = (polyline_length(&drawn), polyline_length(&rest));
            assert!((l - l0).abs() < 0.01 * l0, "frame {k}, blade {blade}: backbone {l} m against {l0} m");
        }
    }
}

#[test]
fn a_released_blade_swings_back_at_its_joints_period_following_the_cpu_mirror_and_decays() {
    let scene = Scene::generate(200, 22);
    let params = ChainParams::default();
    let dt = 1.0 / 60.0;
    // Frame 0 starts every blade at its equilibrium under 8 m/s; then calm.
    let winds: Vec<Wind> = (0..120).map(|k| wind(0.0, if k == 0 { 1.0 } else { 0.0 })).collect();
    let (frames, grid) = run(&scene, params, dt, &winds);
    for blade in [0usize, 7, 50] {
        let b = &scene.blades[blade];
        // The CPU mirror from the wind the GPU read at frame 0, in the blade's frame.
        let root = Vec2::new(b.position[0], b.position[2]);
        let cluster = grid.locate(root.x, root.y);
        let emitters = animation::emitters(&winds[0], 0.0);
        let force = animation::blade_force(&grid, &cluster, &frames[0].corners, &emitters, 0, Attenuation::Cluster, b)
            * KEYFRAME_WIND_SCALE;
        let (across, normal) = bezier::frame(b);
        let w = Vec3::new(force.dot(Vec2::new(across.x, across.z)), 0.0, force.dot(Vec2::new(normal.x, normal.z)));
        let chain = Chain::new(b);
        let mut state: ChainState = chain.equilibrium(w, params);
        let rest_tip = neutral(&scene, blade)[SEGMENTS as usize];
        let mut gpu = Vec::new();
        let mut cpu = Vec::new();
        for (k, frame) in frames.iter().enumerate() {
            if k > 0 {
                chain.step(&mut state, Vec3::ZERO, params, dt as f32);
            }
            gpu.push(backbone(&frame.records, &scene, blade)[SEGMENTS as usize].x - rest_tip.x);
            let tip = chain.controls(&state)[2];
            cpu.push((across * tip.x + Vec3::Y * tip.y + normal * tip.z).x - rest_tip.x);
        }
        // Step for step: the records' quantisation, and f32 on both sides.
        for (k, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
            assert!((g - c).abs() < 2e-3 * b.height, "blade {blade}, frame {k}: GPU {g} against CPU {c}");
        }
        let (period, peaks) = swing(&gpu, dt);
        let joint = std::f32::consts::TAU / params.stiffness.sqrt();
        assert!((period - joint).abs() < 0.1 * joint, "blade {blade}: period {period} s against 2π/√(k/J) = {joint} s");
        assert!(
            peaks.len() >= 3 && peaks.windows(2).all(|p| p[1] < p[0]),
            "blade {blade}: peaks {peaks:?} do not decay"
        );
    }
}

/// The period of a swing about 0 (from its first and last upward zero crossings, in seconds) and
/// the magnitudes of its successive peaks.
fn swing(trace: &[f32], dt: f64) -> (f32, Vec<f32>) {
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

#[test]
fn the_longest_step_and_the_stiffest_constants_do_not_blow_up() {
    let scene = Scene::generate(300, 23);
    let params = ChainParams { stiffness: 400.0, damping: 20.0 };
    // 16 m/s, reversing every 10 steps, at 1/15 s.
    let winds: Vec<Wind> = (0..80).map(|k| wind(if (k / 10) % 2 == 0 { 0.0 } else { 180.0 }, 2.0)).collect();
    let (frames, _) = run(&scene, params, 1.0 / 15.0, &winds);
    for (k, frame) in frames.iter().enumerate() {
        for blade in 0..scene.blades.len() {
            let drawn = backbone(&frame.records, &scene, blade);
            let l0 = polyline_length(&neutral(&scene, blade));
            let l = polyline_length(&drawn);
            assert!((l - l0).abs() < 0.01 * l0, "frame {k}, blade {blade}: backbone {l} m against {l0} m");
            assert!(drawn.iter().all(|p| p.y >= -1e-3 * l0), "frame {k}, blade {blade}: below its root {drawn:?}");
        }
    }
}

#[test]
fn a_thousand_frames_through_the_cull_leave_memory_flat() {
    let scene = Scene::blocks(FieldSpec { size: None, density: 150.0 }, 3);
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(4, Culling::default_for(4));
        let animation = AnimationSettings { mode: Mode::Inertial, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
        let start = scene.default_camera();
        let mut samples = Vec::new();
        for step in 0..1000u64 {
            // Across blocks and back, looking at the sky now and then: the store scrolls and
            // blades are culled and reset.
            let x = start.position.x + 6.0 * ((step / 9) % 2) as f32;
            let pitch = if step % 50 == 49 { 80.0 } else { start.pitch_deg };
            let camera =
                Camera { position: Vec3::new(x, start.position.y, start.position.z), pitch_deg: pitch, ..start };
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
    });
    assert_eq!(messages, Some(0), "validation messages");
    let samples = result.expect("rendered");
    assert_eq!(samples[0], samples[1], "allocated bytes, pending deletions at frames 100 and 1000");
}
