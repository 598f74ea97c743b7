//! The blade class's rows (`render::draw_rows`, issue #30 item 1): one draw per visible tile and
//! LOD bucket inside a multi-draw-indirect (`DrawRows::PerTile`, what `--animation sine-cluster`
//! draws with) against one draw per bucket. The rows draw exactly the picture of the buckets, on
//! a stored field and a block field, batched or not; their count is the (tile, bucket) pairs that
//! draw, as a CPU reference of the cull counts them; and a device without `gl_DrawID` refuses them
//! with one line.

mod support;

use ash::vk;
use glam::Vec3;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::cull_reference::reference_counts_drawn;
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::draw_rows::DrawRows;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::{Camera, Scene};
use meadow::vk::DeviceSelector;

const EXTENT: vk::Extent2D = vk::Extent2D { width: 320, height: 180 };

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) }
}

/// Each camera's picture and cull counts (two frames each, the last kept), keyframed blades
/// posed once per drawn blade (the default with the cull) at a fixed time.
fn render(scene: &Scene, settings: RenderSettings, cameras: &[Camera]) -> Vec<(Vec<u8>, CullCounts)> {
    let (result, messages) = with_device(&options(), false, |device| {
        let mut renderer = Renderer::new(device.clone(), scene, settings, posed())?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let mut out = Vec::new();
        for camera in cameras {
            renderer.render_offscreen(&mut target, camera, 0.7)?;
            let timings = renderer.render_offscreen(&mut target, camera, 0.7)?;
            out.push((target.pixels().to_vec(), timings.cull.expect("the cull ran")));
        }
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(out)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

/// Keyframes posed once per drawn blade (the default with the cull; a row per tile draws pose
/// records or neutral blades).
fn posed() -> AnimationSettings {
    AnimationSettings { eval: meadow::render::animation::Eval::Blade, ..Default::default() }
}

fn settings(rows: DrawRows, blades_per_instance: u32) -> RenderSettings {
    let culling = Culling { rows, ..Culling::default_for(4) };
    RenderSettings { blades_per_instance, ..RenderSettings::offscreen(4, culling) }
}

fn stored_cameras() -> Vec<Camera> {
    let at = |x: f32, z: f32, eye: f32, yaw: f32, pitch: f32| Camera {
        position: Vec3::new(x, eye, z),
        yaw_deg: yaw,
        pitch_deg: pitch,
    };
    vec![at(0.0, 3.6, 1.7, -90.0, -12.0), at(-1.0, 1.0, 1.2, 60.0, -10.0), at(0.5, -0.5, 6.0, 200.0, -70.0)]
}

#[test]
fn a_row_per_tile_draws_the_picture_of_one_draw_per_bucket() {
    let stored = Scene::generate(20_000, 4);
    let blocks = Scene::blocks(FieldSpec { size: None, density: 400.0 }, 1);
    let field_camera = |yaw: f32| {
        let ground = blocks.field.as_ref().expect("a field").ground.height(3.0, -2.0) as f32;
        Camera { position: Vec3::new(3.0, ground + 1.7, -2.0), yaw_deg: yaw, pitch_deg: -10.0 }
    };
    let scenes = [(&stored, stored_cameras()), (&blocks, vec![field_camera(30.0), field_camera(200.0)])];
    for (scene, cameras) in scenes {
        for batch in [32, 1] {
            let buckets = render(scene, settings(DrawRows::PerBucket, batch), &cameras);
            let tiles = render(scene, settings(DrawRows::PerTile, batch), &cameras);
            for (i, ((a, once), (b, rows))) in buckets.iter().zip(&tiles).enumerate() {
                let what = format!("camera {i}, {batch} blades an instance, {}", rows.summary());
                assert!(a == b, "{what}: the rows draw another picture");
                assert_eq!(once.drawn, rows.drawn, "{what}");
                assert_eq!(once.tile_draws, 0, "{what}: one draw per bucket counts no rows");
                // The control: the rows are many draws, more than one a bucket.
                let buckets_drawn = rows.drawn.iter().filter(|&&d| d > 0).count() as u32;
                assert!(rows.total_drawn() > 0 && rows.tile_draws > 2 * buckets_drawn, "{what}");
            }
        }
    }
}

#[test]
fn the_rows_are_the_tiles_that_draw_each_bucket() {
    let scene = Scene::generate(20_000, 4);
    let cameras = stored_cameras();
    // The CPU reference has no depth pyramid.
    let culling = Culling { rows: DrawRows::PerTile, occlusion: false, ..Culling::default_for(4) };
    let settings = RenderSettings::offscreen(4, culling);
    let rendered = render(&scene, settings, &cameras);
    let (reference, messages) = with_device(&options(), false, |device| {
        let renderer = Renderer::new(device.clone(), &scene, settings, posed())?;
        let drawn = (culling.solid_outline, DrawRows::PerTile);
        Ok(cameras
            .iter()
            .map(|c| reference_counts_drawn(&scene, &renderer.frame_uniforms(c, 0.7, EXTENT), drawn))
            .collect::<Vec<_>>())
    });
    assert_eq!(messages, Some(0));
    for (i, ((_, gpu), cpu)) in rendered.iter().zip(reference.expect("built")).enumerate() {
        assert_eq!(*gpu, cpu, "camera {i}: GPU {} / CPU {}", gpu.summary(), cpu.summary());
        assert!(gpu.tile_draws >= gpu.tiles_visible.min(1), "camera {i}: {}", gpu.summary());
    }
}

#[test]
fn the_sine_per_cluster_draws_a_row_per_tile() {
    let scene = Scene::generate(20_000, 4);
    let cameras = &stored_cameras()[..1];
    let (result, messages) = with_device(&options(), false, |device| {
        let cluster = Mode::Sine(meadow::render::animation::sine::SinePhase::Cluster);
        let animation = AnimationSettings { mode: cluster, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), &scene, settings(DrawRows::PerBucket, 32), animation)?;
        let mut target = OffscreenTarget::new(device, EXTENT)?;
        let timings = renderer.render_offscreen(&mut target, &cameras[0], 0.7)?;
        let rows = renderer.settings().culling.rows;
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok((timings.cull.expect("the cull ran"), rows))
    });
    assert_eq!(messages, Some(0), "validation messages");
    let (counts, rows) = result.expect("rendered");
    assert_eq!(rows, DrawRows::PerTile, "the mode chose the rows");
    assert!(counts.tile_draws > 2, "{}", counts.summary());
}

#[test]
fn a_device_without_draw_parameters_refuses_the_sine_per_cluster_in_one_line() {
    let dir = support::scratch("draw-rows-refused");
    let out = dir.join("refused.png");
    let output = support::meadow()
        .env("MEADOW_HIDE", "shaderDrawParameters")
        .args(["render", "--device", support::DEVICE, "--blades", "2000", "--size", "64x36"])
        .args(["--animation", "sine-cluster", "--out"])
        .arg(&out)
        .output()
        .expect("run meadow");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: ") && stderr.contains("shaderDrawParameters"), "{stderr}");
    assert!(!out.exists(), "nothing written");
}
