//! The analytic wind field's pass (`shaders/wind/analytic_corners.comp`; the Perlin field's is its
//! variant `perlin`, with the noise as texels in its set): one dispatch over the
//! cluster corners writes this frame's wind (m/s) and exposure into the frame's corner buffer,
//! from the parameters `AnalyticWind::update` left for the frame (its own uniform block, bound
//! as a uniform block and, for the counts that decide control flow, as a storage buffer) and the
//! frame's emitters. Its own set, no
//! scene sets. First in the frame. Every pass whose shaders sample the corners (through
//! `shaders/wind/wind_field.glsl`: the blades, the blade poses, the bounds view) declares its
//! read of the frame's corners (`PassSetup::wind`), so the graph puts the compute-write →
//! vertex/compute-read barrier before each, and the next frame that writes this slot's corners
//! waits for those reads.

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;

use super::params::Params;
use super::WindSetup;
use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{PassSet, PassSetDesc};
use crate::render::shaders;
use crate::vk::buffer::TexelView;
use crate::vk::descriptor::Resource;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device, Guard};

/// The noise and its mips as RG32F texels, uploaded and waited for: the pass only reads them.
fn upload_noise(device: &Device, texels: &[[f32; 2]]) -> Result<(Buffer, TexelView)> {
    let mut batch = UploadBatch::new(device);
    let usage = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
    let buffer = batch.buffer("perlin noise", texels, usage, &[Access::ComputeShaderRead])?;
    batch.submit()?;
    let buffer = Guard::new(device, buffer);
    let view = TexelView::new(device, &buffer, vk::Format::R32G32_SFLOAT, "perlin noise texels")?;
    Ok((buffer.take(), view))
}

/// Which corner shader a field's pass builds.
pub enum CornerVariant<'a> {
    /// The analytic field's.
    Analytic,
    /// The Perlin field's, over its noise's texels (`perlin::Noise`).
    Perlin(&'a [[f32; 2]]),
    /// The fluid field's (`FLUID_WIND`), over the views of its velocity grid and of its upwind
    /// ghosts' wind (GENERAL layout).
    Fluid(vk::ImageView, vk::ImageView),
}

/// The corners' pipeline, its set per frame in flight and its parameter blocks.
pub struct AnalyticCornersPass {
    pipeline: vk::Pipeline,
    /// The Perlin field's noise (`perlin::Noise`), uploaded by the pass, and its texel view.
    noise: Option<(Buffer, TexelView)>,
    set: PassSet,
    uniforms: PassUniforms,
    /// Each frame's corner buffer.
    corners: Vec<vk::Buffer>,
    /// Corners the buffers hold (every level's).
    capacity: u32,
    params: Rc<RefCell<Params>>,
}

impl AnalyticCornersPass {
    /// Build the pipeline of `variant` and a set per frame in flight over `setup`'s buffers.
    pub fn new(
        device: &Device,
        setup: &WindSetup,
        params: Rc<RefCell<Params>>,
        variant: CornerVariant,
    ) -> Result<Self> {
        let noise = match variant {
            CornerVariant::Perlin(noise) => Some(noise),
            _ => None,
        };
        let fluid = match variant {
            CornerVariant::Fluid(view, inflow) => Some((view, inflow)),
            _ => None,
        };
        let frames = setup.frames.len();
        let size = std::mem::size_of::<Params>() as u64;
        let uniforms = Guard::new(device, PassUniforms::new(device, "wind field", size, frames)?);
        let uploaded = Guard::new(device, noise.map(|n| upload_noise(device, n)).transpose()?);
        let code = match (uploaded.is_some(), fluid.is_some()) {
            (true, _) => shaders::PERLIN_CORNERS_COMP.code(device.profile),
            (false, true) => shaders::FLUID_CORNERS_COMP.code(device.profile),
            (false, false) => shaders::ANALYTIC_CORNERS_COMP.code(device.profile),
        };
        let shaders = [("analytic_corners.comp", code)];
        let desc = PassSetDesc { name: "wind field", shaders: &shaders, before: &[], push: &[], frames };
        let set = PassSet::new(device, &desc, |slot| {
            let (corners, emitters) = setup.frames[slot];
            let mut resources = vec![
                ("WindValues", uniforms.resource(slot)),
                ("WindControl", uniforms.resource(slot)),
                ("Emitters", Resource::Buffer(emitters)),
                ("Corners", Resource::Buffer(corners)),
            ];
            resources.extend(uploaded.as_ref().map(|(_, view)| ("noise_texels", Resource::Texels(view.raw))));
            if let Some((view, inflow)) = fluid {
                resources.extend([("Src", storage_image(view)), ("Inflow", storage_image(inflow))]);
            }
            resources
        })?;
        let set = Guard::new(device, set);
        let pipeline = pipeline::compute(device, "wind field", code, set.layout, &[])?;
        Ok(Self {
            pipeline,
            noise: uploaded.take(),
            set: set.take(),
            uniforms: uniforms.take(),
            corners: setup.frames.iter().map(|(corners, _)| corners.buffer).collect(),
            capacity: setup.corners,
            params,
        })
    }
}

/// A storage image's descriptor (GENERAL layout, no sampler).
pub fn storage_image(view: vk::ImageView) -> Resource {
    Resource::Image(vk::DescriptorImageInfo {
        sampler: vk::Sampler::null(),
        image_view: view,
        image_layout: vk::ImageLayout::GENERAL,
    })
}

impl AnalyticCornersPass {
    /// This frame's corner buffer (written by the dispatch).
    pub fn corners(&self, slot: usize) -> vk::Buffer {
        self.corners[slot]
    }

    /// The parameter block of frame in flight `slot`, for the passes that share it.
    pub fn params_resource(&self, slot: usize) -> Resource {
        self.uniforms.resource(slot)
    }
}

impl Pass for AnalyticCornersPass {
    fn name(&self) -> &'static str {
        "wind field"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.corners[ctx.slot], Access::ComputeShaderWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        // SAFETY: cmd is recording; the pipeline and the set are live and match.
        unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline) };
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        // A row of workgroups per level this frame holds (`Params::shape`: corners a side, levels).
        let shape = self.params.borrow().shape;
        let corners = (shape[0] * shape[0]).max(1);
        let levels = shape[3].max(1).min(self.capacity / corners);
        // SAFETY: as above.
        unsafe { device.raw.cmd_dispatch(cmd, corners.div_ceil(gpu::WIND_GROUP), levels, 1) };
        Ok(())
    }

    fn uniforms(&self, _ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        Some((&self.uniforms, bytemuck::bytes_of(&*self.params.borrow()).to_vec()))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
            if let Some((buffer, view)) = self.noise {
                view.destroy(device);
                buffer.destroy(device);
            }
        }
    }
}
