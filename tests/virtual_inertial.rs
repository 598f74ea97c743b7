//! Belyaev's virtually-inertial blades (§3.3; `render::animation::virtual_blades`,
//! `render::animation::virtual_inertial`), read back from the GPU: the pose records
//! `shaders/animation/virtual_inertial.comp` wrote from the virtual wind
//! `shaders/animation/virtual_blades.comp` stepped at the wind corners, frame by frame, one step a
//! frame, on a stored field by brute force (records by stored blade; the CPU writes the cluster
//! corners, through the analytic wind field, whose wind the test sets between frames).
//!
//! - Under no wind a blade rests at its neutral shape; under a wind towards +x the tips move
//!   towards +x, and the drawn backbone keeps its length within 1 % under the strongest wind.
//! - The drawn blades follow the CPU mirror step for step: upright virtual chains (`Chain::upright`)
//!   at the blade's four corners stepped under the corners' wind, their virtual moments as forces
//!   (`Chain::virtual_forces`) weighted as the wind is, and the blade's static equilibrium under
//!   them (`Chain::equilibrium_under`). A released blade swings at its joints' 2π/√(k/J) within
//!   10 %, and decays.
//! - Under a steady wind a blade reaches the shape of the static-equilibrium solve under that wind.
//! - At the longest step (1/15 s) and the stiffest constants, under a wind that reverses, nothing
//!   blows up.
//! - On a block field the virtual blades' state moves with O: a camera that steps a block away and
//!   back draws the same picture as one that stayed, and one that jumps past the wind's levels and
//!   back (every virtual blade restarted) does not. A thousand frames through the cull leave the
//!   allocated memory flat.

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use ash::vk;
use glam::{Vec2, Vec3};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::chain::{Chain, ChainParams, ChainState, CHAIN_SEGMENTS};
use meadow::render::animation::virtual_inertial::VIRTUAL_HEIGHT;
use meadow::render::animation::{self, AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{bezier, Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{Attenuation, Wind, KEYFRAME_WIND_SCALE};
use pose_records::{
    backbone, neutral, polyline_length, run, swing, thousand_frames_through_the_cull, wind, Frame, SEGMENTS,
};

/// The virtually-inertial blades with `params`.
fn settings(params: ChainParams) -> AnimationSettings {
    AnimationSettings { mode: Mode::VirtualInertial, chain: params, ..Default::default() }
}

/// The CPU mirror of one blade over `frames`: the upright virtual chains at its cluster's four
/// corners, started at their equilibrium under frame 0's corner wind and stepped once a frame
/// under each frame's, and the blade's equilibrium under their virtual forces, weighted as the
/// GPU weights the wind. The tip (world axes, relative to the root) at every frame.
fn cpu_tips(
    scene: &Scene,
    grid: &meadow::scene::clusters::ClusterGrid,
    blade: usize,
    frames: &[Frame],
    params: ChainParams,
    dt: f32,
) -> Vec<Vec3> {
    let b = &scene.blades[blade];
    let cluster = grid.locate(b.position[0], b.position[2]);
    let n = grid.corners_per_side();
    let corners = [cluster.corner, cluster.corner + 1, cluster.corner + n, cluster.corner + n + 1];
    let weights: Vec<f32> = (0..4).map(|j| ((cluster.weights >> (8 * j)) & 0xff) as f32 / 255.0).collect();
    let virtual_chain = Chain::upright(VIRTUAL_HEIGHT);
    let drawn = Chain::new(b);
    let (across, normal) = bezier::frame(b);
    let mut states: Vec<ChainState> = Vec::new();
    let mut tips = Vec::new();
    for (k, frame) in frames.iter().enumerate() {
        let winds: Vec<Vec3> =
            corners.iter().map(|&c| frame.corners[c as usize]).map(|w| Vec3::new(w.x, 0.0, w.z)).collect();
        if k == 0 {
            states = winds.iter().map(|&w| virtual_chain.equilibrium(w, params)).collect();
        } else {
            for (state, &w) in states.iter_mut().zip(&winds) {
                virtual_chain.step(state, w, params, dt);
            }
        }
        let mut force = [Vec3::ZERO; CHAIN_SEGMENTS];
        for (state, weight) in states.iter().zip(&weights) {
            for (f, v) in force.iter_mut().zip(virtual_chain.virtual_forces(state, params)) {
                *f += v * *weight;
            }
        }
        let local = force.map(|f| Vec3::new(f.dot(across), f.y, f.dot(normal)));
        let tip = drawn.controls(&drawn.equilibrium_under(&local, params))[2];
        tips.push(across * tip.x + Vec3::Y * tip.y + normal * tip.z);
    }
    tips
}

#[test]
fn without_wind_blades_rest_at_their_neutral_shape_and_under_wind_the_tips_go_downwind() {
    let scene = Scene::generate(400, 31);
    let params = ChainParams::default();
    let calm: Vec<Wind> = (0..10).map(|_| wind(0.0, 0.0)).collect();
    let (frames, _) = run(&scene, settings(params), 1.0 / 60.0, &calm);
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
    let (frames, _) = run(&scene, settings(params), 1.0 / 60.0, &winds);
    for k in [29, 59] {
        for blade in 0..scene.blades.len() {
            let h = scene.blades[blade].height;
            let drawn = backbone(&frames[k].records, &scene, blade);
            let rest = neutral(&scene, blade);
            let moved = drawn[SEGMENTS as usize] - rest[SEGMENTS as usize];
            assert!(moved.x > 0.05 * h && moved.x > moved.z.abs(), "frame {k}, blade {blade}: tip moved {moved}");
            let (l, l0) = (polyline_length(&drawn), polyline_length(&rest));
            assert!((l - l0).abs() < 0.01 * l0, "frame {k}, blade {blade}: backbone {l} m against {l0} m");
        }
    }
}

#[test]
fn the_drawn_blades_follow_the_cpu_mirror_and_a_released_blade_swings_at_the_joints_period() {
    let scene = Scene::generate(200, 32);
    let params = ChainParams::default();
    let dt = 1.0 / 60.0;
    // Frame 0 starts every virtual blade at its equilibrium under 8 m/s; then calm.
    let winds: Vec<Wind> = (0..120).map(|k| wind(0.0, if k == 0 { 1.0 } else { 0.0 })).collect();
    let (frames, grid) = run(&scene, settings(params), dt, &winds);
    for blade in [0usize, 7, 50] {
        let h = scene.blades[blade].height;
        let rest_tip = neutral(&scene, blade)[SEGMENTS as usize];
        let cpu = cpu_tips(&scene, &grid, blade, &frames, params, dt as f32);
        let mut gpu = Vec::new();
        for (k, frame) in frames.iter().enumerate() {
            let tip = backbone(&frame.records, &scene, blade)[SEGMENTS as usize];
            assert!(
                (tip - cpu[k]).length() < 2e-3 * h,
                "blade {blade}, frame {k}: GPU tip {tip} against CPU {}",
                cpu[k]
            );
            gpu.push(tip.x - rest_tip.x);
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

#[test]
fn under_a_steady_wind_a_blade_reaches_its_static_equilibrium() {
    let scene = Scene::generate(200, 33);
    let params = ChainParams::default();
    // Calm at frame 0, then 8 m/s towards +x for 3 s: the swing decays as e^(−d/2 · t) = e^(−6).
    let winds: Vec<Wind> = (0..181).map(|k| wind(0.0, if k == 0 { 0.0 } else { 1.0 })).collect();
    let (frames, grid) = run(&scene, settings(params), 1.0 / 60.0, &winds);
    let last = frames.last().expect("frames");
    let mut worst = 0.0f32;
    for blade in 0..scene.blades.len() {
        let b = &scene.blades[blade];
        let root = Vec2::new(b.position[0], b.position[2]);
        let cluster = grid.locate(root.x, root.y);
        let emitters = animation::emitters(&winds[180], 0.0);
        let force = animation::blade_force(&grid, &cluster, &last.corners, &emitters, 0, Attenuation::Cluster, b)
            * KEYFRAME_WIND_SCALE;
        let (across, normal) = bezier::frame(b);
        let w = Vec3::new(force.dot(Vec2::new(across.x, across.z)), 0.0, force.dot(Vec2::new(normal.x, normal.z)));
        let chain = Chain::new(b);
        let tip = chain.controls(&chain.equilibrium(w, params))[2];
        let expected = across * tip.x + Vec3::Y * tip.y + normal * tip.z;
        let drawn = backbone(&last.records, &scene, blade)[SEGMENTS as usize];
        let rest = neutral(&scene, blade)[SEGMENTS as usize];
        assert!((expected - rest).x > 0.05 * b.height, "blade {blade}: the solve's tip {expected} barely moved");
        let off = (drawn - expected).length() / b.height;
        worst = worst.max(off);
        assert!(off < 0.005, "blade {blade}: tip {drawn} against the static solve's {expected} ({off} of its height)");
    }
    assert!(worst > 0.0, "the drawn tips equal the solve's to the bit: the records were not read");
}

#[test]
fn the_longest_step_and_the_stiffest_constants_do_not_blow_up() {
    let scene = Scene::generate(300, 34);
    let params = ChainParams { stiffness: 400.0, damping: 20.0 };
    // 16 m/s, reversing every 10 steps, at 1/15 s.
    let winds: Vec<Wind> = (0..80).map(|k| wind(if (k / 10) % 2 == 0 { 0.0 } else { 180.0 }, 2.0)).collect();
    let (frames, _) = run(&scene, settings(params), 1.0 / 15.0, &winds);
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

/// Pictures of a block field released from 8 m/s at frame 0, calm after, the camera at `start`
/// but at `away` (x offset in metres) over frames 10..13; the picture of frame 20.
fn field_picture(device: &std::sync::Arc<meadow::vk::Device>, away: f32) -> meadow::Result<Vec<u8>> {
    let scene = Scene::blocks(FieldSpec { size: None, density: 60.0 }, 5);
    let culling = Culling { view_distance: 40.0, ..Culling::default_for(4) };
    let settings = RenderSettings::offscreen(4, culling);
    let animation = AnimationSettings { mode: Mode::VirtualInertial, ..Default::default() };
    let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
    let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
    let start = scene.default_camera();
    for k in 0..=20u32 {
        *renderer.wind_mut() = wind(0.0, if k == 0 { 1.0 } else { 0.0 });
        let x = start.position.x + if (10..13).contains(&k) { away } else { 0.0 };
        let camera = Camera { position: Vec3::new(x, start.position.y, start.position.z), ..start };
        renderer.render_offscreen(&mut target, &camera, ((f64::from(k) + 0.5) / 60.0) as f32)?;
    }
    let picture = target.pixels().to_vec();
    drop(renderer);
    // SAFETY: render_offscreen waited for its frame; the renderer is gone.
    unsafe { target.destroy(device) };
    Ok(picture)
}

#[test]
fn the_virtual_blades_move_with_the_origin_and_memory_stays_flat() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let stayed = field_picture(device, 0.0)?;
        // A block away and back (O moves by 4 m twice; levels 0 and 1 carry their state exactly).
        let stepped = field_picture(device, 4.0)?;
        // Past the outermost wind level (4 096 m) and back: every virtual blade restarts, at rest.
        let jumped = field_picture(device, 10_000.0)?;
        let samples = thousand_frames_through_the_cull(device, Mode::VirtualInertial)?;
        Ok((stayed, stepped, jumped, samples))
    });
    assert_eq!(messages, Some(0), "validation messages");
    let (stayed, stepped, jumped, samples) = result.expect("rendered");
    assert!(stayed == stepped, "a block away and back changed the picture: the state did not move with O");
    assert!(stayed != jumped, "a restart of every virtual blade left the picture unchanged: the test cannot see one");
    assert_eq!(samples[0], samples[1], "allocated bytes, pending deletions at frames 100 and 1000");
}
