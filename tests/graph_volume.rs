//! 3-D storage images in the graph: a pass defined here, with its own shader
//! (`tests/shaders/volume_step.comp`, compiled once per step) and its own set, runs a chain of
//! four dependent dispatches over 3-D images made by `vk::image` (`ImageDesc::volume`): it
//! writes a source grid (rgba16f, a storage write), gathers a 7-point stencil of the previous
//! frame's grid (a storage read) and of the source (sampled) into a scratch grid, relaxes that
//! into this frame's grid, then samples this frame's grid into a buffer and copies the previous
//! one into another. The two grids are a temporal pair declared once. Every layout transition
//! and barrier is the graph's (UNDEFINED → GENERAL on first use, storage write → storage read
//! and → sampled read between steps, sampled or copied → written again on later frames):
//! validation and synchronization validation stay at 0 messages, and after several frames both
//! grids match a CPU reference exactly (small integers, exact in float).

#[path = "support/glsl.rs"]
mod glsl;
mod support;

use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::culling::Culling;
use meadow::render::graph::{Declaration, Pass, PassContext, Temporal};
use meadow::render::recording::{PassSet, PassSetDesc};
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::vk::descriptor::Resource as Descriptor;
use meadow::vk::upload::UploadBatch;
use meadow::vk::{image, pipeline, Access, Buffer, BufferDesc, Device, DeviceSelector, Image, ImageDesc, Resource};

/// The grids' size (the shader's `DIMS`).
const DIMS: [usize; 3] = [8, 6, 4];
const TEXELS: usize = DIMS[0] * DIMS[1] * DIMS[2];
const FRAMES: usize = 5;

/// The chain's images and buffers (raw handles: the test owns them), its set and pipelines.
struct VolumePass {
    pair: Temporal,
    source: vk::Image,
    scratch: vk::Image,
    /// This frame's grid, sampled; the previous grid, copied.
    sampled: vk::Buffer,
    copied: vk::Buffer,
    /// Set `side` reads side 1 - side and writes side `side`.
    set: PassSet,
    /// One pipeline per step.
    pipelines: Vec<vk::Pipeline>,
}

impl Pass for VolumePass {
    fn name(&self) -> &'static str {
        "test volume"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        let declaration = Declaration::compute()
            .step("source")
            .image(self.source, Access::ComputeShaderWrite)
            .step("stencil")
            .previous(self.pair, Access::ComputeShaderRead)
            .image(self.source, Access::ComputeShaderSampledRead)
            .image(self.scratch, Access::ComputeShaderWrite)
            .step("relax")
            .image(self.scratch, Access::ComputeShaderRead)
            .current(self.pair, Access::ComputeShaderWrite)
            .step("read back")
            .current(self.pair, Access::ComputeShaderSampledRead)
            .buffer(self.sampled, Access::ComputeShaderWrite)
            .previous(self.pair, Access::TransferRead)
            .buffer(self.copied, Access::TransferWrite)
            // No commands: the barrier that makes both buffers readable by the host.
            .step("to host")
            .buffer(self.sampled, Access::HostRead)
            .buffer(self.copied, Access::HostRead);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> meadow::Result<()> {
        let Some(&pipeline) = self.pipelines.get(ctx.step) else { return Ok(()) };
        let (device, bind) = (ctx.device, vk::PipelineBindPoint::COMPUTE);
        let pair = ctx.temporal(self.pair);
        self.set.bind(device, cmd, bind, pair.current);
        let push = [ctx.clock.index as u32];
        // SAFETY: cmd is recording outside a rendering instance; the set is bound and its images
        // are in the layouts the graph's barriers left them in.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, pipeline);
            device.raw.cmd_push_constants(
                cmd,
                self.set.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                &push[0].to_ne_bytes(),
            );
            device.raw.cmd_dispatch(cmd, 2, 2, 1);
        }
        if ctx.step == 3 {
            let Resource::Image { raw, .. } = pair.previous() else { unreachable!("the pair holds images") };
            let extent = vk::Extent3D { width: DIMS[0] as u32, height: DIMS[1] as u32, depth: DIMS[2] as u32 };
            image::record_copy_to_buffer(device, cmd, raw, extent, self.copied);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for pipeline in self.pipelines {
                meadow::vk::live::destroyed(pipeline);
                device.raw.destroy_pipeline(pipeline, None);
            }
            self.set.destroy(device);
        }
    }
}

/// Index of texel `(x, y, z)`.
fn at(x: usize, y: usize, z: usize) -> usize {
    (z * DIMS[1] + y) * DIMS[0] + x
}

/// The sum of the six face neighbours of `(x, y, z)` in `grid`, clamped at the edges.
fn neighbours(grid: &[u32], [x, y, z]: [usize; 3]) -> u32 {
    let c = |v: usize, d: i64, n: usize| (v as i64 + d).clamp(0, n as i64 - 1) as usize;
    let (nx, ny, nz) = (DIMS[0], DIMS[1], DIMS[2]);
    [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
        .iter()
        .map(|&(dx, dy, dz)| grid[at(c(x, dx, nx), c(y, dy, ny), c(z, dz, nz))])
        .sum()
}

/// The CPU reference of one frame's chain from the previous grid (integers, as the shader's
/// floats hold them exactly).
fn reference_frame(previous: &[u32], frame: usize) -> Vec<u32> {
    let cells = || (0..DIMS[2]).flat_map(|z| (0..DIMS[1]).flat_map(move |y| (0..DIMS[0]).map(move |x| [x, y, z])));
    let scratch: Vec<u32> = cells()
        .map(|[x, y, z]| {
            let a = (x + 2 * y + 3 * z + frame) % 8;
            let b = (x * y + z + frame) % 4;
            (neighbours(previous, [x, y, z]) + 3 * previous[at(x, y, z)] + (a + 2 * b) as u32) % 4096
        })
        .collect();
    cells().map(|p| (neighbours(&scratch, p) + scratch[at(p[0], p[1], p[2])]) % 4096).collect()
}

fn initial() -> Vec<u32> {
    (0..TEXELS).map(|i| ((i * 7 + i / 8 * 3 + i / 48 * 5) % 32) as u32).collect()
}

fn floats(buffer: &Buffer) -> Vec<f32> {
    bytemuck::cast_slice::<u8, f32>(&buffer.mapped()[..4 * TEXELS]).to_vec()
}

struct Outcome {
    sampled: Vec<f32>,
    copied: Vec<f32>,
    current: usize,
    submitted: u64,
}

/// The grids: the pair (side 1 uploaded, read by the first frame), the source and the scratch.
fn grids(device: &Arc<Device>) -> meadow::Result<[Image; 4]> {
    use vk::ImageUsageFlags as U;
    let extent = vk::Extent3D { width: DIMS[0] as u32, height: DIMS[1] as u32, depth: DIMS[2] as u32 };
    let (grid, rgba) = (vk::Format::R32_SFLOAT, vk::Format::R16G16B16A16_SFLOAT);
    let usage = U::STORAGE | U::SAMPLED | U::TRANSFER_SRC | U::TRANSFER_DST;
    let texels: Vec<f32> = initial().iter().map(|&v| v as f32).collect();
    let mut upload = UploadBatch::new(device);
    let side1 = upload.image(
        &ImageDesc::volume("grid side 1", grid, extent, usage),
        bytemuck::cast_slice(&texels),
        &[Access::ComputeShaderRead],
    )?;
    upload.submit()?;
    Ok([
        Image::new(device, &ImageDesc::volume("grid side 0", grid, extent, usage))?,
        side1,
        Image::new(device, &ImageDesc::volume("grid source", rgba, extent, U::STORAGE | U::SAMPLED))?,
        Image::new(device, &ImageDesc::volume("grid scratch", grid, extent, U::STORAGE))?,
    ])
}

fn run(device: &Arc<Device>) -> meadow::Result<Outcome> {
    let images = grids(device)?;
    let bytes = 4 * TEXELS as u64;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
    let sampled = Buffer::new(device, &BufferDesc::readback("grid sampled", bytes, usage))?;
    let copied = Buffer::new(device, &BufferDesc::readback("grid copied", bytes, usage))?;
    let sampler = image::clamped_sampler(device, vk::Filter::NEAREST, "grid sampler")?;
    let spirv: Vec<Vec<u8>> =
        (0..4).map(|s| glsl::compile_with("volume_step.comp", &[&format!("-DSTEP={s}")])).collect();
    let names = ["volume step 0", "volume step 1", "volume step 2", "volume step 3"];
    let shaders: Vec<(&str, &[u8])> = names.iter().zip(&spirv).map(|(n, s)| (*n, s.as_slice())).collect();
    let range = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 4 };
    let desc = PassSetDesc { name: "test volume", shaders: &shaders, before: &[], push: &[range], frames: 2 };
    let view = |image: &Image, layout| {
        Descriptor::Image(vk::DescriptorImageInfo { sampler, image_view: image.view, image_layout: layout })
    };
    let (storage, read) = (vk::ImageLayout::GENERAL, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
    let set = PassSet::new(device, &desc, |side| {
        vec![
            ("Source", view(&images[2], storage)),
            ("Previous", view(&images[1 - side], storage)),
            ("SourceSampled", view(&images[2], read)),
            ("Scratch", view(&images[3], storage)),
            ("Current", view(&images[side], storage)),
            ("CurrentSampled", view(&images[side], read)),
            ("Readback", Descriptor::Buffer(sampled.descriptor())),
        ]
    })?;
    let mut pipelines = Vec::new();
    for (name, spirv) in &shaders {
        pipelines.push(pipeline::compute(device, name, spirv, set.layout, &[])?);
    }
    let scene = meadow::scene::Scene::generate(300, 3);
    let settings = RenderSettings::offscreen(2, Culling { enabled: false, ..Culling::default_for(2) });
    let mut renderer = Renderer::new(device.clone(), &scene, settings, Default::default())?;
    let pair = renderer.temporal([Resource::color(images[0].raw), Resource::color(images[1].raw)]);
    renderer.import(Resource::color(images[1].raw), &[Access::ComputeShaderRead]);
    for image in [&images[0], &images[2], &images[3]] {
        renderer.import(Resource::color(image.raw), &[Access::Nothing]);
    }
    let (source, scratch) = (images[2].raw, images[3].raw);
    renderer.add_pass(Box::new(VolumePass {
        pair,
        source,
        scratch,
        sampled: sampled.raw,
        copied: copied.raw,
        set,
        pipelines,
    }));
    let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 16, height: 16 })?;
    let camera = meadow::scene::Camera::default_for(&scene.terrain);
    for _ in 0..FRAMES {
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
    }
    renderer.wait_all_frames()?;
    let outcome = Outcome {
        sampled: floats(&sampled),
        copied: floats(&copied),
        current: renderer.temporal_pair(pair).current,
        submitted: renderer.frames_submitted(),
    };
    drop(renderer);
    // SAFETY: the renderer waited for the device on drop.
    unsafe {
        target.destroy(device);
        sampled.destroy(device);
        copied.destroy(device);
        for image in images {
            image.destroy(device);
        }
        meadow::vk::live::destroyed(sampler);
        device.raw.destroy_sampler(sampler, None);
    }
    Ok(outcome)
}

#[test]
fn a_test_pass_chains_dispatches_over_3d_storage_images_with_derived_barriers() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (outcome, messages) = with_device(&options, false, run);
    let outcome = outcome.expect("frames");
    // A missing barrier or layout transition between the steps or the frames is a message.
    assert_eq!(messages, Some(0));
    assert_eq!(outcome.submitted, FRAMES as u64);
    // Five swaps: side 1 is written next.
    assert_eq!(outcome.current, FRAMES % 2);
    let mut states = vec![initial()];
    for frame in 0..FRAMES {
        let next = reference_frame(states.last().expect("a state"), frame);
        states.push(next);
    }
    let as_floats = |v: &[u32]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    assert!(states[FRAMES].iter().any(|&v| v != states[FRAMES][0]), "the grid is not uniform");
    assert!(
        outcome.sampled == as_floats(&states[FRAMES]),
        "the last frame's grid (sampled) differs from the CPU reference"
    );
    assert!(
        outcome.copied == as_floats(&states[FRAMES - 1]),
        "the frame before's grid (copied) differs from the CPU reference"
    );
}
