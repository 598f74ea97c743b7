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

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use glam::{Vec2, Vec3};
use meadow::render::animation::chain::{Chain, ChainParams, ChainState};
use meadow::render::animation::{self, AnimationSettings, Mode};
use meadow::scene::{bezier, Scene};
use meadow::wind::{Attenuation, Wind, KEYFRAME_WIND_SCALE};
use pose_records::{backbone, memory_through_the_cull, neutral, polyline_length, run, swing, wind, SEGMENTS};

/// The inertial chains with `params`.
fn settings(params: ChainParams) -> AnimationSettings {
    AnimationSettings { mode: Mode::Inertial, chain: params, ..Default::default() }
}

#[test]
fn without_wind_blades_rest_at_their_neutral_shape_and_under_wind_the_tips_go_downwind() {
    let scene = Scene::generate(400, 21);
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
    let (frames, grid) = run(&scene, settings(params), dt, &winds);
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

#[test]
fn the_longest_step_and_the_stiffest_constants_do_not_blow_up() {
    let scene = Scene::generate(300, 23);
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

#[test]
fn a_thousand_frames_through_the_cull_leave_memory_flat() {
    let samples = memory_through_the_cull(Mode::Inertial);
    assert_eq!(samples[0], samples[1], "allocated bytes, pending deletions at frames 100 and 1000");
}
