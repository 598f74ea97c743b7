//! A pass defined outside the library, with its own shader (`tests/shaders/chain_step.comp`,
//! compiled here), its own set (`PassSet`: the layout reflected from the shader, resources given
//! by the names the GLSL declares) and its own uniform block (`PassUniforms`, written by the
//! graph each frame), added to the renderer's frames: a chain of three dependent dispatches over
//! a ping-pong buffer declared once as a temporal pair. The graph derives the barriers between
//! the steps (synchronization validation checks them), the result matches a CPU reference whose
//! scale and bias change every frame as the uniforms do, the pair advances once per submitted
//! frame, and a frame failed by `MEADOW_INJECT_SUBMIT_FAILURE` neither swaps it nor moves the
//! frame clock.
//!
//! Alone in its test binary: it sets `MEADOW_INJECT_SUBMIT_FAILURE` for the renderer it builds.

#[path = "support/glsl.rs"]
mod glsl;
mod support;

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::culling::Culling;
use meadow::render::graph::{Declaration, Pass, PassContext, PassUniforms, Temporal};
use meadow::render::recording::{PassSet, PassSetDesc};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::{pipeline, Access, Buffer, BufferDesc, Device, DeviceSelector, Resource};

/// Values in the ping-pong buffer.
const N: u32 = 1000;
/// The submission that fails (1-based).
const FAILING: usize = 3;

/// Frames in flight of the test's renderer.
const FRAMES: usize = 2;

/// The scale and bias of frame `index` (the pass's uniform block, `Params` in the shader).
fn params(index: u64) -> [u32; 2] {
    [3 + (index % 4) as u32, 1 + index as u32]
}

/// The chain: gather the previous frame's values into a scratch buffer, scale them into this
/// frame's side, mix that side in place; then hand it to the host.
struct ChainPass {
    pair: Temporal,
    scratch: vk::Buffer,
    /// Set `side * FRAMES + slot` reads side 1 - side, writes side `side` and reads slot `slot`'s
    /// uniforms.
    set: PassSet,
    pipeline: vk::Pipeline,
    uniforms: PassUniforms,
    /// The frame index each recording saw (`PassContext::clock`).
    frames_seen: Rc<RefCell<Vec<u64>>>,
}

impl Pass for ChainPass {
    fn name(&self) -> &'static str {
        "test chain"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .step("gather")
            .previous(self.pair, Access::ComputeShaderRead)
            .buffer(self.scratch, Access::ComputeShaderWrite)
            .step("scale")
            .buffer(self.scratch, Access::ComputeShaderRead)
            .current(self.pair, Access::ComputeShaderWrite)
            .step("mix")
            .current(self.pair, Access::ComputeShaderRead)
            .current(self.pair, Access::ComputeShaderWrite)
            // No commands: the barrier that makes this frame's side readable by the host.
            .step("to host")
            .current(self.pair, Access::HostRead);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        if ctx.step == 0 {
            self.frames_seen.borrow_mut().push(ctx.clock.index);
        }
        if ctx.step == 3 {
            return Ok(());
        }
        let set = ctx.temporal(self.pair).current * FRAMES + ctx.slot;
        let push = [ctx.step as u32, N, ctx.clock.index as u32];
        let (device, bind) = (ctx.device, vk::PipelineBindPoint::COMPUTE);
        self.set.bind(device, cmd, bind, set);
        // SAFETY: cmd is recording outside a rendering instance; the set is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, self.pipeline);
            let stages = vk::ShaderStageFlags::COMPUTE;
            device.raw.cmd_push_constants(cmd, self.set.layout, stages, 0, bytemuck::cast_slice(&push));
            device.raw.cmd_dispatch(cmd, N.div_ceil(64), 1, 1);
        }
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        Some((&self.uniforms, bytemuck::cast_slice(&params(ctx.clock.index)).to_vec()))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            meadow::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
        }
    }
}

/// The CPU reference of one frame's chain from the previous values.
fn reference_frame(previous: &[u32], frame: u32) -> Vec<u32> {
    let n = previous.len();
    let scratch: Vec<u32> = (0..n).map(|i| previous[(i + 1) % n].wrapping_add(i as u32).wrapping_add(frame)).collect();
    let [scale, bias] = params(u64::from(frame));
    (0..n)
        .map(|i| {
            let c = scratch[(i + 7) % n].wrapping_mul(scale).wrapping_add(bias);
            c ^ (c >> 5)
        })
        .collect()
}

fn words(buffer: &Buffer) -> Vec<u32> {
    bytemuck::cast_slice::<u8, u32>(buffer.mapped()).to_vec()
}

struct Outcome {
    /// Which frames failed.
    failed: Vec<bool>,
    frames_seen: Vec<u64>,
    submitted: u64,
    /// The pair's sides after the frames, and which one the next frame writes.
    sides: [Vec<u32>; 2],
    current: usize,
    /// Step names of the last frame's timings, in order.
    steps: Vec<(&'static str, &'static str, f64)>,
    first_pass: &'static str,
}

fn run_chain(device: &std::sync::Arc<Device>, frames: usize) -> meadow::Result<Outcome> {
    let initial: Vec<u32> = (0..N).map(|i| i.wrapping_mul(2_654_435_761)).collect();
    let bytes = 4 * u64::from(N);
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let mut sides = [
        Buffer::new(device, &BufferDesc::readback("chain side 0", bytes, usage))?,
        Buffer::new(device, &BufferDesc::readback("chain side 1", bytes, usage))?,
    ];
    sides[0].write(0, &vec![0u32; N as usize]);
    // The first frame reads side 1 (previous) and writes side 0 (current).
    sides[1].write(0, &initial);
    let scratch = Buffer::new(device, &BufferDesc::gpu_only("chain scratch", bytes, usage))?;
    let spirv = glsl::compile("chain_step.comp");
    let uniforms = PassUniforms::new(device, "test chain", 8, FRAMES)?;
    let range = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 12 };
    let desc = PassSetDesc {
        name: "test chain",
        shaders: &[("chain_step.comp", &spirv)],
        before: &[],
        push: &[range],
        frames: 2 * FRAMES,
    };
    let whole = |b: &Buffer| Descriptor::Buffer(b.descriptor());
    let set = PassSet::new(device, &desc, |index| {
        let (side, slot) = (index / FRAMES, index % FRAMES);
        vec![
            ("Previous", whole(&sides[1 - side])),
            ("Current", whole(&sides[side])),
            ("Scratch", whole(&scratch)),
            ("Params", uniforms.resource(slot)),
        ]
    })?;
    let pipeline = pipeline::compute(device, "test chain", &spirv, set.layout, &[])?;
    let scene = meadow::scene::Scene::generate(300, 3);
    let settings = RenderSettings {
        frames_in_flight: FRAMES,
        ..RenderSettings::offscreen(2, Culling { enabled: false, ..Culling::default_for(2) })
    };
    let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
    let pair = renderer.temporal([Resource::Buffer(sides[0].raw), Resource::Buffer(sides[1].raw)]);
    let frames_seen = Rc::new(RefCell::new(Vec::new()));
    let pass = ChainPass { pair, scratch: scratch.raw, set, pipeline, uniforms, frames_seen: frames_seen.clone() };
    renderer.add_pass(Box::new(pass));
    let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 16, height: 16 })?;
    let camera = meadow::scene::Camera::default_for(&scene.terrain);
    let mut failed = Vec::new();
    let mut last = None;
    for _ in 0..frames {
        match renderer.render_offscreen(&mut target, &camera, 0.0) {
            Ok(timings) => {
                failed.push(false);
                last = Some(timings);
            }
            Err(e) => {
                assert!(e.to_string().contains("injected failure"), "{e}");
                failed.push(true);
            }
        }
    }
    renderer.wait_all_frames()?;
    let last = last.expect("a frame rendered");
    let outcome = Outcome {
        failed,
        frames_seen: frames_seen.borrow().clone(),
        submitted: renderer.frames_submitted(),
        sides: [words(&sides[0]), words(&sides[1])],
        current: renderer.temporal_pair(pair).current,
        steps: last.steps.iter().map(|s| (s.pass, s.name, s.ms)).collect(),
        first_pass: last.passes.first().map_or("", |p| p.name),
    };
    drop(renderer);
    // SAFETY: the renderer waited for the device on drop.
    unsafe {
        target.destroy(device);
        scratch.destroy(device);
        for side in sides {
            side.destroy(device);
        }
    }
    Ok(outcome)
}

#[test]
fn a_test_pass_chains_three_dispatches_over_a_ping_pong_buffer_once_per_submitted_frame() {
    std::env::set_var("MEADOW_INJECT_SUBMIT_FAILURE", FAILING.to_string());
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let frames = 5;
    let (outcome, messages) = with_device(&options, false, |device| run_chain(device, frames));
    let outcome = outcome.expect("frames");
    // Any missing barrier between the dispatches is a synchronization-validation message.
    assert_eq!(messages, Some(0));
    let mut expected_failed = vec![false; frames];
    expected_failed[FAILING - 1] = true;
    assert_eq!(outcome.failed, expected_failed);
    // The failed frame was recorded (index 2) but not submitted: the retry is frame 2 again.
    assert_eq!(outcome.frames_seen, [0, 1, 2, 2, 3]);
    assert_eq!(outcome.submitted, 4);
    // Four swaps: side 0 is written next, side 1 holds the last frame's values, side 0 the one
    // before (a dropped frame that swapped would leave them the other way, one frame stale).
    assert_eq!(outcome.current, 0);
    let mut states = vec![(0..N).map(|i| i.wrapping_mul(2_654_435_761)).collect::<Vec<u32>>()];
    for frame in 0..4 {
        let next = reference_frame(states.last().expect("a state"), frame);
        states.push(next);
    }
    assert!(outcome.sides[1] == states[4], "the last frame's values differ from the CPU reference");
    assert!(outcome.sides[0] == states[3], "the frame before's values differ from the CPU reference");
    // The pass runs first, its named steps measured inside it.
    assert_eq!(outcome.first_pass, "test chain");
    let names: Vec<_> = outcome.steps.iter().map(|&(pass, name, _)| (pass, name)).collect();
    let chain = |name| ("test chain", name);
    assert_eq!(names, [chain("gather"), chain("scale"), chain("mix"), chain("to host")]);
    assert!(outcome.steps.iter().all(|&(_, _, ms)| ms.is_finite() && ms >= 0.0), "{:?}", outcome.steps);
}
