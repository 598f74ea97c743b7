//! Resolve pass (`--msaa` or `--fade blend`, `render::msaa`): the last scene pass. One triangle
//! over the frame's target reads the linear colour the scene passes drew (`ctx.target`), averages
//! each pixel's samples in linear space and writes the encoded result into the target
//! (`ctx.output`). Like the depth pyramid, its set (one per frame in flight) is pointed at the
//! frame's image when the pass is recorded: that set's previous use ended with the slot's fence.

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Attachment, Declaration, Load, Pass, PassContext, Rendering};
use crate::render::passes;
use crate::render::recording::{PassSet, PassSetDesc};
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{image, pipeline, Access, Device, Guard, Resource};

/// The pipeline and its set per frame in flight (set 0, `PassSet`, written when recorded), with
/// the sampler the multisampled colour is read with (nearest, clamped).
pub struct ResolvePass {
    pipeline: vk::Pipeline,
    sets: PassSet,
    sampler: vk::Sampler,
}

impl ResolvePass {
    /// Build the pipeline for targets of `format` from a scene of `samples` samples per pixel
    /// (1: `--fade blend`'s single-sampled one); `constants` decide the encoding (`ENCODE_SRGB`:
    /// the target's, not the linear scene's).
    pub fn new(
        device: &Device,
        (format, samples): (vk::Format, u32),
        constants: &Specialization,
        frames: usize,
    ) -> Result<Self> {
        let fragment = if samples > 1 { shaders::RESOLVE_FRAG } else { shaders::RESOLVE_SINGLE_FRAG };
        let stages = [
            ("resolve.vert", shaders::RESOLVE_VERT.code(device.profile)),
            ("resolve.frag", fragment.code(device.profile)),
        ];
        let desc = PassSetDesc { name: "resolve", shaders: &stages, before: &[], push: &[], frames };
        let sets = Guard::new(device, PassSet::unwritten(device, &desc)?);
        let sampler = Guard::new(device, image::clamped_sampler(device, vk::Filter::NEAREST, "resolve sampler")?);
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "resolve",
                vertex: shaders::RESOLVE_VERT.code(device.profile),
                fragment: fragment.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: vk::PolygonMode::FILL,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: true,
                color_format: format,
                depth_format: vk::Format::UNDEFINED,
                layout: sets.layout,
                constants: &constants.named(),
                vertex_stride: 0,
                samples: vk::SampleCountFlags::TYPE_1,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        Ok(Self { pipeline, sets: sets.take(), sampler: sampler.take() })
    }
}

impl Pass for ResolvePass {
    fn name(&self) -> &'static str {
        "resolve"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let output = ctx.output;
        let color = Attachment { image: output.color, view: output.color_view, load: Load::Discard, store: true };
        let rendering = Rendering {
            extent: output.extent,
            color: Some(color),
            depth: None,
            pipeline: self.pipeline,
            depth_write: false,
            secondary: false,
        };
        Some(
            Declaration::graphics(rendering).uses(Resource::color(ctx.target.color), Access::FragmentShaderSampledRead),
        )
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let scene = vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: ctx.target.color_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // The slot's previous frame has finished (its fence was waited): its set is free.
        self.sets.write(device, ctx.slot, "resolve", &[("scene_color", Descriptor::Image(scene))])?;
        passes::set_full_viewport(device, cmd, ctx.output.extent);
        // SAFETY: cmd is recording inside this pass's rendering instance; the set matches the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
        }
        self.sets.bind(device, cmd, vk::PipelineBindPoint::GRAPHICS, ctx.slot);
        // SAFETY: as above; the set is bound.
        unsafe {
            device.raw.cmd_draw(cmd, 3, 1, 0, 0);
        }
        Ok(())
    }

    fn replay_key(&self, ctx: &PassContext) -> Option<u64> {
        // Its set, written in `record`, names the multisampled colour view.
        Some(ash::vk::Handle::as_raw(ctx.target.color_view))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            self.sets.destroy(device);
        }
    }
}
