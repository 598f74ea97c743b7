//! Resolve pass (`--msaa`, `render::msaa`): the last scene pass. One triangle over the frame's
//! target reads the multisampled colour the scene passes drew (`ctx.target`), averages each
//! pixel's samples in linear space and writes the encoded result into the target
//! (`ctx.output`). Like the depth pyramid, its set (one per frame in flight) is pointed at the
//! frame's image when the pass is recorded: that set's previous use ended with the slot's fence.

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Attachment, Declaration, Load, Pass, PassContext, Rendering};
use crate::render::passes;
use crate::render::shaders;
use crate::vk::descriptor::{self, Binding, Resource as Descriptor};
use crate::vk::{pipeline, Access, Device, Resource};

/// The pipeline, its set per frame in flight and the sampler the multisampled colour is read with.
pub struct ResolvePass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    sampler: vk::Sampler,
}

fn bindings() -> [Binding; 1] {
    let fs = vk::ShaderStageFlags::FRAGMENT;
    [Binding { binding: 0, kind: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages: fs }]
}

impl ResolvePass {
    /// Build the pipeline for targets of `format`; `constants` decide the encoding
    /// (`SPEC_ENCODE_SRGB`: the target's, not the multisampled scene's).
    pub fn new(device: &Device, format: vk::Format, constants: &[u32], frames: usize) -> Result<Self> {
        let mut pass = Self {
            pipeline: vk::Pipeline::null(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            sets: Vec::new(),
            sampler: vk::Sampler::null(),
        };
        if let Err(e) = pass.build(device, format, constants, frames) {
            // SAFETY: nothing was submitted with the pass; null handles are ignored.
            unsafe { Box::new(pass).destroy(device) };
            return Err(e);
        }
        Ok(pass)
    }

    fn build(&mut self, device: &Device, format: vk::Format, constants: &[u32], frames: usize) -> Result<()> {
        self.set_layout = descriptor::set_layout(device, "resolve set layout", &bindings())?;
        self.layout = pipeline::layout(device, "resolve layout", &[self.set_layout], &[])?;
        let (pool, sets) =
            descriptor::allocate_sets(device, "resolve sets", self.set_layout, &bindings(), frames as u32)?;
        (self.pool, self.sets) = (pool, sets);
        self.sampler = crate::vk::image::clamped_sampler(device, vk::Filter::NEAREST, "resolve sampler")?;
        self.pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "resolve",
                vertex: shaders::RESOLVE_VERT,
                fragment: shaders::RESOLVE_FRAG,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: vk::PolygonMode::FILL,
                depth_compare: vk::CompareOp::ALWAYS,
                color_format: format,
                depth_format: vk::Format::UNDEFINED,
                layout: self.layout,
                constants,
                vertex_stride: 0,
                samples: vk::SampleCountFlags::TYPE_1,
                alpha_to_coverage: false,
            },
        )?;
        Ok(())
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
            secondary: false,
        };
        Some(
            Declaration::graphics(rendering).uses(Resource::color(ctx.target.color), Access::FragmentShaderSampledRead),
        )
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let set = self.sets[ctx.slot];
        let scene = vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: ctx.target.color_view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // The slot's previous frame has finished (its fence was waited): its set is free.
        descriptor::write(device, set, &[(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, Descriptor::Image(scene))]);
        passes::set_full_viewport(device, cmd, ctx.output.extent);
        // SAFETY: cmd is recording inside this pass's rendering instance; the set matches the layout.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, self.layout, 0, &[set], &[]);
            device.raw.cmd_draw(cmd, 3, 1, 0, 0);
        }
        Ok(())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op; the sets go with the pool.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            crate::vk::live::destroyed(self.set_layout);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
