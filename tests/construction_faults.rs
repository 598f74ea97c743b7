//! Every failure during a renderer's construction frees what was built (issue 28 item 7): a
//! device-memory allocation, then a shader module (out of host memory), is made to fail at the
//! first two calls from each distinct call site of the construction (found by running it once),
//! in configurations that together build every pass, model and target; after each failure meadow's count of live Vulkan objects
//! (`vk::live`) and the allocator's bytes are back where they were. A construction here is what
//! a run builds before and around its first frames: the renderer, its overlay, a set 0 of a
//! pass's own (`Renderer::frame_instance`), a target, a frame, a rebuild to other passes and
//! model, and a frame of those.
//!
//! One test in this file: the counters are the process's.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::error::Result;
use meadow::render::animation::{AnimationSettings, Eval, Mode};
use meadow::render::culling::Culling;
use meadow::render::msaa::Msaa;
use meadow::render::overlay::OverlayFrame;
use meadow::render::submission::{Strategy, Submission};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::field::FieldSpec;
use meadow::scene::Scene;
use meadow::vk::fault::{self, Fault};
use meadow::vk::{live, Device, DeviceSelector};

const EXTENT: vk::Extent2D = vk::Extent2D { width: 64, height: 48 };

/// A scene, what the renderer is built with, and what it is rebuilt with.
struct Config {
    name: &'static str,
    scene: Scene,
    built: (RenderSettings, AnimationSettings),
    rebuilt: (RenderSettings, AnimationSettings),
}

fn animation(mode: Mode, eval: Eval) -> AnimationSettings {
    AnimationSettings { mode, eval, ..Default::default() }
}

fn configs() -> Vec<Config> {
    let culled = RenderSettings { frames_in_flight: 2, ..RenderSettings::offscreen(4, Culling::default_for(4)) };
    let brute = RenderSettings { frames_in_flight: 2, ..RenderSettings::offscreen(4, Culling::brute_force(4)) };
    let msaa = Msaa { samples: 4, alpha_to_coverage: true };
    vec![
        Config {
            // The cull with occlusion, per-blade poses and levels, MSAA's targets and resolve;
            // rebuilt to brute force with vertex evaluation, drawn from pre-recorded commands.
            name: "culled",
            scene: Scene::generate(600, 1),
            built: (RenderSettings { msaa, ..culled }, animation(Mode::Texture, Eval::Blade)),
            rebuilt: (
                RenderSettings { submission: Submission { strategy: Strategy::Prerecorded, clusters: 1 }, ..brute },
                animation(Mode::Uniform, Eval::Vertex),
            ),
        },
        Config {
            // The floor reference and indirect cluster draws; rebuilt to the static blades.
            name: "floor",
            scene: Scene::generate(600, 2),
            built: (
                RenderSettings {
                    floor: true,
                    submission: Submission { strategy: Strategy::Mdi, clusters: 8 },
                    ..brute
                },
                animation(Mode::Static, Eval::Vertex),
            ),
            rebuilt: (RenderSettings { debug_bounds: true, ..brute }, animation(Mode::Static, Eval::Vertex)),
        },
        Config {
            // A block field (its relief grid) with per-vertex keyframes (the blade pass's own set
            // of the response's tables); rebuilt to uniform keyframes per blade.
            name: "field",
            scene: Scene::blocks(FieldSpec { size: None, density: 40.0 }, 3),
            built: (culled, animation(Mode::Texture, Eval::Vertex)),
            rebuilt: (culled, animation(Mode::Uniform, Eval::Blade)),
        },
    ]
}

/// An overlay frame with nothing in it: the overlay's pipeline and sets are made.
fn empty_overlay() -> OverlayFrame {
    OverlayFrame { primitives: Vec::new(), textures: Default::default(), pixels_per_point: 1.0 }
}

/// Build, draw, rebuild and draw `config`; everything is destroyed on the way out.
fn construct(device: &Arc<Device>, config: &Config) -> Result<()> {
    let (settings, animation) = config.built.clone();
    let mut renderer = Renderer::new(device.clone(), &config.scene, settings, animation)?;
    renderer.set_overlay(Some(empty_overlay()))?;
    // A set 0 of a pass's own (a bake's): its uniform blocks, one per frame in flight, and sets.
    let instance = renderer.frame_instance("construction faults")?;
    // SAFETY: no frame used it.
    unsafe { instance.destroy(device) };
    let mut target = OffscreenTarget::new(device, EXTENT)?;
    let camera = config.scene.default_camera();
    let drawn = renderer.render_offscreen(&mut target, &camera, 0.0).and_then(|_| {
        let (settings, animation) = config.rebuilt.clone();
        renderer.rebuild(&config.scene, settings, animation)?;
        renderer.render_offscreen(&mut target, &camera, 0.1)
    });
    drop(renderer);
    // SAFETY: the renderer waited for the device when it dropped.
    unsafe { target.destroy(device) };
    drawn.map(|_| ())
}

/// The calls of `kind` that one construction of `config` makes, and the ones to fail: the first
/// two calls from each distinct call site (its stack through meadow's source) not failed in an
/// earlier configuration (`seen`), so that each site fails once with nothing before it from the
/// same site and once after one (a loop's second turn, a ring's second slot), instead of every
/// call in turn.
fn aims(device: &Arc<Device>, config: &Config, kind: Fault, seen: &mut HashMap<String, u32>) -> (usize, Vec<u64>) {
    fault::record_sites(kind);
    let built = construct(device, config);
    let sites = fault::sites(kind);
    let calls = sites.len();
    built.unwrap_or_else(|e| panic!("{}: {e}", config.name));
    let mut aims = Vec::new();
    for (call, site) in sites.into_iter().enumerate() {
        let times = seen.entry(site).or_default();
        *times += 1;
        if *times <= 2 {
            aims.push(call as u64 + 1);
        }
    }
    (calls, aims)
}

/// Fail each aimed call of `kind` (`aims`): each failure is the injected one (`said`), and leaves
/// no object and no allocation behind. Returns the calls made and how many were failed.
fn fail_each(
    device: &Arc<Device>,
    (config, kind): (&Config, Fault),
    seen: &mut HashMap<String, u32>,
    said: &dyn Fn(&str) -> bool,
) -> (usize, usize) {
    let bytes = || device.allocator().generate_report().total_allocated_bytes;
    let (calls, aims) = aims(device, config, kind, seen);
    let (objects, allocated) = (live::total(), bytes());
    for &nth in &aims {
        fault::fail_in(kind, Some(nth));
        let built = construct(device, config);
        fault::fail_in(kind, None);
        let Err(e) = built else { panic!("{}: call {nth} of {calls} did not fail the construction", config.name) };
        let message = e.to_string();
        assert!(said(&message), "{} at call {nth}: not the injected failure: {message}", config.name);
        assert_eq!(live::total(), objects, "{} at call {nth} ({message}): left {:?}", config.name, live::by_type());
        assert_eq!(bytes(), allocated, "{} at call {nth} ({message}): memory left allocated", config.name);
    }
    (calls, aims.len())
}

#[test]
fn every_failure_while_building_a_renderer_frees_what_was_built() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (counts, messages) = with_device(&options, false, |device| {
        let mut counts = Vec::new();
        let (mut allocations, mut modules_seen) = (HashMap::new(), HashMap::new());
        for config in configs() {
            let memory = (&config, Fault::Allocation);
            let memory = fail_each(device, memory, &mut allocations, &|e| e.contains("out of device memory"));
            let modules = (&config, Fault::HostMemory);
            let modules = fail_each(device, modules, &mut modules_seen, &|e| e.contains("out of host memory"));
            counts.push((config.name, memory, modules));
        }
        Ok(counts)
    });
    assert_eq!(messages, Some(0), "validation messages (leaks are reported when the device goes)");
    let counts = counts.expect("every configuration built once nothing failed");
    for (name, (memory, memory_failed), (modules, modules_failed)) in counts {
        // The control: the sweeps reached the construction's calls (terrain, cull, blades,
        // overlay… each allocate and make pipelines), from many sites.
        println!(
            "{name}: {memory_failed} of {memory} allocations, {modules_failed} of {modules} shader modules failed"
        );
        assert!(
            memory_failed >= 15 && modules_failed >= 8,
            "{name}: {memory_failed} allocations, {modules_failed} modules"
        );
    }
    assert_eq!(live::total(), 0, "left alive: {:?}", live::by_type());
}
