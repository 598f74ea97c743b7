//! Meadow's count of live Vulkan objects (`vk::live`) returns to zero when a renderer, its
//! targets and the device are gone, after frames, a rebuild and the cull: every handle the `vk`
//! layer creates is destroyed once.

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, Scene};
use meadow::vk::{live, DeviceSelector};

#[test]
fn every_object_created_is_destroyed() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (during, messages) = with_device(&options, false, |device| {
        let scene = Scene::generate(2000, 1);
        let settings = RenderSettings { frames_in_flight: 2, ..RenderSettings::offscreen(4, Culling::default_for(4)) };
        let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 64 })?;
        let camera = Camera::default_for(&scene.terrain);
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let brute = RenderSettings { frames_in_flight: 2, ..RenderSettings::offscreen(4, Culling::brute_force(4)) };
        renderer.rebuild(&scene, brute, Default::default())?;
        renderer.render_offscreen(&mut target, &camera, 0.1)?;
        let during = live::total();
        drop(renderer);
        // SAFETY: the renderer waited for the device on drop.
        unsafe { target.destroy(device) };
        Ok(during)
    });
    assert_eq!(messages, Some(0));
    let during = during.expect("rendered");
    assert!(during > 20, "the counter saw the renderer's objects: {during}");
    assert_eq!(live::total(), 0, "left alive: {:?}", live::by_type());
}
