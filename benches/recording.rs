//! CPU cost of one frame on the real renderer and device, without submitting it
//! (`Renderer::record_only`): the frame's uniforms and corner forces written, then the blade-pose,
//! terrain and blade passes recorded into an offscreen target. One renderer per variant over the
//! same 40 000-blade scene (8 segments). `cargo bench --bench recording`.
//!
//! The corner forces are part of a frame's CPU work and are included: on this 10 m field, 121
//! corners under the gusty default wind. The `no_wind` variant leaves them nearly free, which
//! isolates the cost of recording the commands.
//!
//! Needs a Vulkan device (lavapipe is enough): without one, it says so and measures nothing.

use std::time::Duration;

use ash::vk;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use meadow::app::{check_scene, with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, Scene};
use meadow::vk::Device;
use meadow::wind::{GlobalWind, Wind};

const BLADES: u32 = 40_000;
const SEGMENTS: u32 = 8;
const SIZE: (u32, u32) = (640, 360);

/// (name, mode, eval, blades per instance, the CLI's default wind or none)
const VARIANTS: [(&str, Mode, Eval, u32, bool); 7] = [
    ("static", Mode::Static, Eval::Vertex, 1, true),
    ("texture", Mode::Texture, Eval::Vertex, 1, true),
    ("uniform", Mode::Uniform, Eval::Vertex, 1, true),
    ("texture_eval_blade", Mode::Texture, Eval::Blade, 1, true),
    ("uniform_eval_blade", Mode::Uniform, Eval::Blade, 1, true),
    ("texture_64_blades_per_instance", Mode::Texture, Eval::Vertex, 64, true),
    ("texture_no_wind", Mode::Texture, Eval::Vertex, 1, false),
];

fn bench_variants(c: &mut Criterion, device: &std::sync::Arc<Device>) -> meadow::Result<()> {
    let scene = Scene::generate(BLADES, 1);
    let camera = Camera::default_for(&scene.terrain);
    let extent = vk::Extent2D { width: SIZE.0, height: SIZE.1 };
    let target = OffscreenTarget::new(device, extent)?;
    let view = target.view();
    let mut group = c.benchmark_group(format!("record_frame/{BLADES}_blades_{SEGMENTS}_segments"));
    let result = (|| {
        for (name, mode, eval, blades_per_instance, windy) in VARIANTS {
            // The CLI's default wind, or still air.
            let global = windy.then_some(GlobalWind { direction_deg: 30.0, strength: 0.3, gusts: true });
            let animation =
                AnimationSettings { mode, eval, wind: Wind { global, ..Default::default() }, ..Default::default() };
            check_scene(device, BLADES, SEGMENTS, SIZE, &animation, false, (false, Default::default(), false))?;
            // Recording cost of the thesis path: every stored blade, no cull pass.
            let brute_force = meadow::render::culling::Culling::brute_force(SEGMENTS);
            let settings = RenderSettings { blades_per_instance, ..RenderSettings::offscreen(SEGMENTS, brute_force) };
            let mut renderer = Renderer::new(device.clone(), &scene, settings, animation)?;
            let mut failure = None;
            group.bench_function(BenchmarkId::from_parameter(name), |b| {
                b.iter(|| {
                    if let Err(e) = renderer.record_only(&view, &camera, 1.0) {
                        failure.get_or_insert(e);
                    }
                })
            });
            if let Some(e) = failure {
                return Err(e);
            }
        }
        Ok(())
    })();
    group.finish();
    // SAFETY: nothing recorded into the target was submitted, and every renderer is dropped.
    unsafe { target.destroy(device) };
    result
}

fn recording(c: &mut Criterion) {
    // Benchmarks run without validation: the layers would dominate the recording cost.
    let mut had_device = false;
    let (result, _) = with_device(&GpuOptions::default(), false, |device| {
        had_device = true;
        println!("recording on {}", device.info.name);
        bench_variants(c, device)
    });
    match result {
        Ok(()) => {}
        Err(e) if !had_device => println!("record_frame: skipped, no Vulkan device: {e}"),
        Err(e) => panic!("record_frame: {e}"),
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = recording
}
criterion_main!(benches);
