//! Shader modules and pipelines (graphics with dynamic rendering, compute). No vertex input
//! state: all geometry is pulled from storage buffers in the vertex shader.

use ash::vk;

use crate::error::{Error, Result, VkContext};
use crate::vk::device::Device;
use crate::vk::guard::Guard;

/// Create a shader module from SPIR-V bytes (as embedded from `OUT_DIR`).
pub fn shader_module(device: &Device, name: &str, spirv: &[u8]) -> Result<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
        .map_err(|e| Error::Environment(format!("shader {name} is not valid SPIR-V: {e}")))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    if super::fault::fails(super::fault::Fault::HostMemory) {
        return Err(Error::vulkan("vkCreateShaderModule (injected failure)", vk::Result::ERROR_OUT_OF_HOST_MEMORY));
    }
    // SAFETY: valid SPIR-V produced by glslang at build time.
    let module =
        super::live::created(unsafe { device.raw.create_shader_module(&info, None) }.vk("vkCreateShaderModule")?);
    device.set_name(module, name);
    Ok(module)
}

/// Create a named pipeline layout.
pub fn layout(
    device: &Device,
    name: &str,
    sets: &[vk::DescriptorSetLayout],
    push_constants: &[vk::PushConstantRange],
) -> Result<vk::PipelineLayout> {
    let info = vk::PipelineLayoutCreateInfo::default().set_layouts(sets).push_constant_ranges(push_constants);
    // SAFETY: valid create info.
    let layout =
        super::live::created(unsafe { device.raw.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?);
    device.set_name(layout, name);
    Ok(layout)
}

/// Description of a graphics pipeline rendering into one colour and one depth attachment.
#[derive(Clone, Copy, Debug)]
pub struct GraphicsDesc<'a> {
    /// Debug name.
    pub name: &'a str,
    /// Vertex shader SPIR-V.
    pub vertex: &'a [u8],
    /// Fragment shader SPIR-V.
    pub fragment: &'a [u8],
    /// Primitive topology.
    pub topology: vk::PrimitiveTopology,
    /// Face culling.
    pub cull: vk::CullModeFlags,
    /// Polygon mode (FILL, or LINE for wireframe).
    pub polygon: vk::PolygonMode,
    /// Depth comparison (meadow uses reversed Z: GREATER).
    pub depth_compare: vk::CompareOp,
    /// Whether fragments that pass the test write their depth. A pipeline that only tests (blended
    /// plants, decals) draws in a pass whose `graph::Rendering::depth_write` is false.
    pub depth_write: bool,
    /// Colour attachment format.
    pub color_format: vk::Format,
    /// Depth attachment format.
    pub depth_format: vk::Format,
    /// Pipeline layout.
    pub layout: vk::PipelineLayout,
    /// Specialization constants of every stage, by the names their GLSL gives them
    /// (`specialization`); empty: the shaders' defaults.
    pub constants: &'a [(&'a str, u32)],
    /// Stride of a vertex buffer with one `vec3` at location 0, or 0 for none (vertex pulling).
    pub vertex_stride: u32,
    /// Rasterization samples (the attachments' sample count).
    pub samples: vk::SampleCountFlags,
    /// How fragments combine with the colour attachment.
    pub blend: Blend,
}

/// How a pipeline's fragments combine with its colour attachment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Blend {
    /// The fragment replaces the pixel (the scene passes).
    #[default]
    Opaque,
    /// Premultiplied alpha, `colour = src + (1 - src.a) dst` (egui's overlay). The attachment's
    /// alpha becomes `src.a (1 - dst.a) + dst.a`, as egui_glow blends: an opaque target stays
    /// opaque.
    PremultipliedAlpha,
}

impl Blend {
    /// The attachment's blend state.
    fn attachment(self) -> vk::PipelineColorBlendAttachmentState {
        let opaque = vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA);
        match self {
            Blend::Opaque => opaque,
            Blend::PremultipliedAlpha => opaque
                .blend_enable(true)
                .src_color_blend_factor(vk::BlendFactor::ONE)
                .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_DST_ALPHA)
                .dst_alpha_blend_factor(vk::BlendFactor::ONE)
                .alpha_blend_op(vk::BlendOp::ADD),
        }
    }
}

/// The specialization of one stage (`name` names it in errors): each constant `spirv` declares
/// (`reflect::spec_constants`, `constant_id` and name) takes the value `constants` gives by its
/// name, so no id is kept outside the GLSL. A declared constant that `constants` does not give
/// is an error naming it; a value no constant of this stage declares is left out (one list
/// serves every stage and pipeline of a configuration). Empty `constants`: no specialization,
/// the shader's defaults. Map entries and their data.
pub fn specialization(
    name: &str,
    spirv: &[u8],
    constants: &[(&str, u32)],
) -> Result<(Vec<vk::SpecializationMapEntry>, Vec<u32>)> {
    let (mut entries, mut data) = (Vec::new(), Vec::new());
    if constants.is_empty() {
        return Ok((entries, data));
    }
    for (id, constant) in super::reflect::spec_constants(name, spirv)? {
        let Some(&(_, value)) = constants.iter().find(|(n, _)| *n == constant) else {
            return Err(Error::Internal(format!(
                "{name}: the shader declares specialization constant `{constant}` (constant_id {id}) and the \
                 pipeline gives it no value"
            )));
        };
        entries.push(vk::SpecializationMapEntry { constant_id: id, offset: 4 * data.len() as u32, size: 4 });
        data.push(value);
    }
    Ok((entries, data))
}

/// The vertex buffer binding and its one `vec3` attribute at location 0 for `stride` (unused
/// when `stride` is 0: vertex pulling).
fn vertex_input(stride: u32) -> ([vk::VertexInputBindingDescription; 1], [vk::VertexInputAttributeDescription; 1]) {
    let bindings = [vk::VertexInputBindingDescription { binding: 0, stride, input_rate: vk::VertexInputRate::VERTEX }];
    let attributes = [vk::VertexInputAttributeDescription {
        location: 0,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    }];
    (bindings, attributes)
}

/// Vertex and fragment modules of `desc`; neither is left behind if one fails.
fn graphics_modules(device: &Device, desc: &GraphicsDesc) -> Result<(vk::ShaderModule, vk::ShaderModule)> {
    let vs = Guard::new(device, shader_module(device, &format!("{} vs", desc.name), desc.vertex)?);
    let fs = shader_module(device, &format!("{} fs", desc.name), desc.fragment)?;
    Ok((vs.take(), fs))
}

/// Build a graphics pipeline with dynamic viewport and scissor.
pub fn graphics(device: &Device, desc: &GraphicsDesc) -> Result<vk::Pipeline> {
    let (vertex, fragment) = (
        specialization(&format!("{} vs", desc.name), desc.vertex, desc.constants)?,
        specialization(&format!("{} fs", desc.name), desc.fragment, desc.constants)?,
    );
    let (vs, fs) = graphics_modules(device, desc)?;
    let (vertex, fragment) = (
        vk::SpecializationInfo::default().map_entries(&vertex.0).data(bytemuck::cast_slice(&vertex.1)),
        vk::SpecializationInfo::default().map_entries(&fragment.0).data(bytemuck::cast_slice(&fragment.1)),
    );
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vs)
            .name(c"main")
            .specialization_info(&vertex),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(fs)
            .name(c"main")
            .specialization_info(&fragment),
    ];
    let (bindings, attributes) = vertex_input(desc.vertex_stride);
    let vertex_input = if desc.vertex_stride == 0 {
        vk::PipelineVertexInputStateCreateInfo::default()
    } else {
        vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes)
    };
    let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
    let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(desc.polygon)
        .cull_mode(desc.cull)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
    // No depth attachment (`UNDEFINED`): no depth test.
    let has_depth = desc.depth_format != vk::Format::UNDEFINED;
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(has_depth)
        .depth_write_enable(has_depth && desc.depth_write)
        .depth_compare_op(desc.depth_compare);
    let blend_attachments = [desc.blend.attachment()];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = [desc.color_format];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(desc.depth_format);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&input_assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(desc.layout)
        .push_next(&mut rendering);
    // SAFETY: all state structs are alive for the call.
    let result = unsafe { device.raw.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
    // SAFETY: modules are not needed after pipeline creation.
    unsafe {
        super::live::destroyed(vs);
        device.raw.destroy_shader_module(vs, None);
        super::live::destroyed(fs);
        device.raw.destroy_shader_module(fs, None);
    }
    let pipeline =
        super::live::created(result.map_err(|(_, result)| Error::vulkan("vkCreateGraphicsPipelines", result))?[0]);
    device.set_name(pipeline, desc.name);
    Ok(pipeline)
}

/// Build a compute pipeline.
pub fn compute(
    device: &Device,
    name: &str,
    spirv: &[u8],
    layout: vk::PipelineLayout,
    constants: &[(&str, u32)],
) -> Result<vk::Pipeline> {
    let (entries, data) = specialization(name, spirv, constants)?;
    let module = shader_module(device, name, spirv)?;
    let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(bytemuck::cast_slice(&data));
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main")
        .specialization_info(&specialization);
    let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout);
    // SAFETY: valid create info.
    let result = unsafe { device.raw.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
    // SAFETY: not needed after creation.
    unsafe {
        super::live::destroyed(module);
        device.raw.destroy_shader_module(module, None)
    };
    let pipeline =
        super::live::created(result.map_err(|(_, result)| Error::vulkan("vkCreateComputePipelines", result))?[0]);
    device.set_name(pipeline, name);
    Ok(pipeline)
}
