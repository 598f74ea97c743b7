//! Belyaev's Perlin wind (§3.2, `render::wind::perlin`, `--wind-field perlin`) on lavapipe:
//! - the GPU's corners (the corner pass's variant `perlin`, through the cull) equal the CPU's
//!   (the brute-force path's `perlin::corner_winds`, the same arithmetic) with a point source and
//!   a calm area on, and they are not the analytic field's;
//! - the field varies over the ground and moves with time;
//! - blades lean with it: under a wind towards +x every tip moves towards +x (read back);
//! - on a block field, every corner of the eight levels (each layer at its level's mip) equals the
//!   CPU's `perlin::wind_at` on the same parameters, at the origin and 100 km from it.

#[path = "support/pose_records.rs"]
mod pose_records;
mod support;

use ash::vk;
use glam::{Vec2, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::sine::SinePhase;
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::field_gpu::Origin;
use meadow::render::wind::perlin::{self, Noise};
use meadow::render::wind::{FieldKind, WindInput};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;
use meadow::wind::{CalmArea, GlobalWind, PointSource, Wind};
use pose_records::{backbone, neutral, SEGMENTS};

/// The corners' wind (velocity x, y, z in m/s, exposure) after one frame at `time`, culled (the
/// GPU's pass) or by brute force (the CPU's).
fn corners(scene: &Scene, field: FieldKind, culled: bool, wind: &Wind, time: f32) -> Vec<Vec4> {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let culling = if culled { Culling::default_for(4) } else { Culling::brute_force(4) };
        let settings = RenderSettings::offscreen(4, culling);
        let animation = AnimationSettings { wind: wind.clone(), wind_field: field, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
        renderer.render_offscreen(&mut target, &Camera::default_for(&scene.terrain), time)?;
        let corners = renderer.read_wind_corners(0)?.into_iter().map(Vec4::from).collect();
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame; the renderer is gone.
        unsafe { target.destroy(device) };
        Ok(corners)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

fn largest_difference(a: &[Vec4], b: &[Vec4]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f32::max)
}

#[test]
fn the_gpus_corners_equal_the_cpus_and_are_not_the_analytic_fields() {
    let scene = Scene::generate(20_000, 4);
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 30.0, strength: 0.5, gusts: true }),
        sources: vec![PointSource {
            position: Vec2::new(1.0, -1.0),
            power: 0.3,
            sigma: 2.0,
            velocity: Vec2::ZERO,
            height: 0.5,
        }],
        calm: vec![CalmArea { min: Vec2::new(-3.0, -3.0), max: Vec2::new(-1.0, -1.0) }],
        ..Default::default()
    };
    let gpu = corners(&scene, FieldKind::Perlin, true, &wind, 1.7);
    let cpu = corners(&scene, FieldKind::Perlin, false, &wind, 1.7);
    let worst = largest_difference(&gpu, &cpu);
    assert!(worst < 1e-4, "the GPU's Perlin corners differ from the CPU's by {worst} m/s");
    // The calm area blocks it, as the analytic field's does.
    assert!(gpu.iter().any(|c| c.w == 0.0) && gpu.iter().any(|c| c.w == 1.0));
    // The controls: the field is not the analytic one, it varies over the ground, and it moves.
    let analytic = corners(&scene, FieldKind::Analytic, true, &wind, 1.7);
    assert!(largest_difference(&gpu, &analytic) > 0.5, "the Perlin field is the analytic one");
    let open: Vec<f32> = gpu.iter().filter(|c| c.w == 1.0).map(|c| c.x).collect();
    let (low, high) = open.iter().fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    assert!(high - low > 1.0, "the wind's x varies from {low} to {high} m/s");
    let later = corners(&scene, FieldKind::Perlin, true, &wind, 2.7);
    assert!(largest_difference(&gpu, &later) > 0.2, "the field moves with time");
}

#[test]
fn under_a_perlin_wind_towards_plus_x_every_tip_moves_towards_plus_x() {
    let scene = Scene::generate(1500, 13);
    let animation =
        AnimationSettings { mode: Mode::Sine(SinePhase::Object), wind_field: FieldKind::Perlin, ..Default::default() };
    let (frames, _) = pose_records::run(&scene, animation, 1.0 / 60.0, &[pose_records::wind(0.0, 0.5)]);
    let frame = &frames[0];
    assert!(frame.corners.iter().all(|c| c.x > 0.5), "the wind blows towards +x at every corner");
    for blade in 0..scene.blades.len() {
        let tip =
            backbone(&frame.records, &scene, blade)[SEGMENTS as usize] - neutral(&scene, blade)[SEGMENTS as usize];
        assert!(tip.x > 0.0, "blade {blade}'s tip moved {tip}");
    }
}

#[test]
fn every_level_of_a_block_field_matches_the_cpu_at_the_origin_and_100_km_out() {
    let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 1);
    let relief = scene.field.as_ref().expect("a field").ground.relief().expect("a relief");
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 40.0, strength: 0.4, gusts: false }), ..Default::default() };
    let noise = Noise::generate();
    for x in [0.0f32, 100_000.0] {
        let ground = relief.height(f64::from(x), 3.0) as f32;
        let camera = Camera { position: glam::Vec3::new(x, ground + 1.7, 3.0), yaw_deg: 30.0, pitch_deg: -10.0 };
        let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
        let (result, messages) = with_device(&options, false, |device| {
            let settings = RenderSettings::offscreen(4, Culling { view_distance: 40.0, ..Culling::default_for(4) });
            let animation =
                AnimationSettings { wind: wind.clone(), wind_field: FieldKind::Perlin, ..Default::default() };
            let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
            let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 96, height: 54 })?;
            renderer.render_offscreen(&mut target, &camera, 1.25)?;
            let corners: Vec<Vec4> = renderer.read_wind_corners(0)?.into_iter().map(Vec4::from).collect();
            let out = (corners, renderer.cluster_grid(), renderer.wind_levels());
            drop(renderer);
            // SAFETY: render_offscreen waited for its frame.
            unsafe { target.destroy(device) };
            Ok(out)
        });
        assert_eq!(messages, Some(0), "validation messages");
        let (corners, grid, levels) = result.expect("rendered");
        let input = WindInput {
            grid: &grid,
            levels: levels.len() as u32,
            wind: &wind,
            attenuation: Default::default(),
            time: 1.25f32 as f64,
            origin: Origin::under(&camera).world,
            cpu_corners: false,
            camera: glam::DVec3::ZERO,
            dt: 1.0 / 60.0,
            ground: None,
        };
        let params = perlin::frame_params(&input);
        let per_level = levels[0].corner_count() as usize;
        assert_eq!(corners.len(), levels.len() * per_level);
        let mut mips = std::collections::BTreeSet::new();
        for (i, gpu) in corners.iter().enumerate() {
            let (level, local) = (i / per_level, (i % per_level) as u32);
            let q = levels[level].corner_position(local);
            let cpu = perlin::wind_at(&noise, &params, q, level);
            let delta = (Vec2::new(gpu.x, gpu.z) - cpu).abs().max_element();
            assert!(delta < 1e-4 * (1.0 + cpu.length()), "x {x}: level {level} corner {local}: GPU {gpu} CPU {cpu}");
            mips.extend(params.perlin_mips[level][..3].iter().copied());
        }
        // The levels the field holds (those its blades reach: 3 at this 40 m view) sample coarser
        // mips as their spacing grows, from the finest (measured: mips 0 to 3; `mip_for`'s unit
        // test reaches the 1² mean).
        assert!(mips.contains(&0) && mips.iter().any(|&m| m >= 3), "{mips:?}");
    }
}
