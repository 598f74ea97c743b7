//! The blade class's rows per tile (`render::draw_rows`) when the visible list is full and the scan
//! thins every bucket evenly (`capacity_scale`, `shaders/cull/cull.glsl`): each row covers exactly
//! its tile's thinned entries, so the rows draw the picture of one draw per bucket, blade for
//! blade. The list's capacity is hidden with `MEADOW_HIDE=maxStorageBufferRange=N` (the placed
//! levels of 4 segments, 120 bytes a record, hold N / 120 entries), set before this process makes
//! its first device: this file holds one test, so nothing else reads the variable first.

mod support;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Eval};
use meadow::render::culling::{CullCounts, Culling};
use meadow::render::draw_rows::DrawRows;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::Scene;
use meadow::vk::DeviceSelector;

fn render(scene: &Scene, rows: DrawRows) -> (Vec<u8>, CullCounts) {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let settings = RenderSettings::offscreen(4, Culling { rows, ..Culling::default_for(4) });
        let animation = AnimationSettings { eval: Eval::Blade, ..Default::default() };
        let mut renderer = Renderer::new(device.clone(), scene, settings, animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let timings = renderer.render_offscreen(&mut target, &scene.default_camera(), 0.5)?;
        let out = (target.pixels().to_vec(), timings.cull.expect("the cull ran"));
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(out)
    });
    assert_eq!(messages, Some(0), "validation messages");
    result.expect("rendered")
}

#[test]
fn thinned_rows_draw_the_picture_of_thinned_buckets() {
    // 6 553 entries, under the 10 250 the default view of this field keeps.
    std::env::set_var("MEADOW_HIDE", "maxStorageBufferRange=786432");
    let scene = Scene::generate(20_000, 4);
    let (buckets, once) = render(&scene, DrawRows::PerBucket);
    let (tiles, rows) = render(&scene, DrawRows::PerTile);
    // The control: the list was full, and the scan thinned it.
    assert!(once.capacity_scale() < 1.0, "{}", once.summary());
    assert_eq!(once.drawn, rows.drawn, "{} / {}", once.summary(), rows.summary());
    assert!(rows.tile_draws > 0, "{}", rows.summary());
    assert!(buckets == tiles, "thinned rows draw another picture: {}", rows.summary());
}
