//! The thesis' response: every blade takes one of a table of precomputed poses (keyframes, ch.
//! 3), selected by the force on it (eq. 3.10–3.12) and blended with its neighbours (eq.
//! 3.13/3.14). The table lives in a texture (4.4.1) or a uniform array (4.4.2); the selection
//! runs per vertex in the blade shader (as the thesis did: `blades/blade.vert`'s variant
//! `keyframes`), or once per blade in the blade-pose compute pass that writes the renderer's pose
//! records (`--eval blade`, the thesis' ch. 7 future work). Its resources — the texture, the
//! uniform array and its uniform block `KeyframeShape` — are declared by
//! `shaders/animation/keyframes.glsl` in the own set of each pass that includes it, and given by
//! those names.

use glam::Vec3;

use crate::error::Result;
use crate::keyframes::{KeyframeLayout, KeyframeTable, Representation};
use crate::render::animation::pose_pass::{PosePass, PoseShader};
use crate::render::animation::response::{BladeInput, BladeResponse, ResponseSetup};
use crate::render::animation::{AnimationSettings, Eval, KeyframeTexture, KeyframeUniforms, Mode};
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Destroy, Device, Guard, Resource};
use crate::wind::KEYFRAME_WIND_SCALE;
use ash::vk;

/// What the keyframe texture is read as, by the blade pass (per vertex) and the pose pass.
const READS: [Access; 2] = [Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead];
/// What its uniform array and shape are read as.
const UNIFORM_READS: [Access; 2] = [Access::VertexShaderUniformRead, Access::ComputeShaderUniformRead];

/// Keyframed blades.
pub struct KeyframeResponse {
    settings: AnimationSettings,
    /// The table on the CPU (`tip_offset`).
    table: KeyframeTable,
    keyframes: KeyframeTexture,
    words: KeyframeUniforms,
    /// The response's uniform block (`KeyframeShape`): magnitudes, angles, records per pose.
    shape: Buffer,
}

impl KeyframeResponse {
    /// Generate the table of `settings` for `segments` and upload it both ways, with its shape.
    pub fn new(device: &Device, settings: &AnimationSettings, segments: u32) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let (keyframes, table) = KeyframeTexture::new(&mut batch, segments, settings)?;
        let keyframes = Guard::new(device, keyframes);
        let words = Guard::new(device, KeyframeUniforms::new(&mut batch, &table, settings.packing)?);
        let layout: KeyframeLayout = keyframes.layout;
        let records = match settings.representation {
            Representation::Vertex => segments,
            Representation::Curve => 3,
        };
        let usage = vk::BufferUsageFlags::UNIFORM_BUFFER;
        let shape = [layout.magnitudes, layout.angles, records, 0u32];
        let shape = Guard::new(device, batch.buffer("keyframe shape", &shape, usage, &UNIFORM_READS)?);
        // The batch waits for its submission, or never submits.
        batch.submit()?;
        Ok(Self {
            settings: settings.clone(),
            table,
            keyframes: keyframes.take(),
            words: words.take(),
            shape: shape.take(),
        })
    }

    fn per_blade(&self) -> bool {
        self.settings.eval == Eval::Blade
    }

    /// The response's resources by the names `shaders/animation/keyframes.glsl` declares.
    pub fn resources(&self) -> Vec<(&'static str, Descriptor)> {
        let image = vk::DescriptorImageInfo {
            sampler: self.keyframes.sampler,
            image_view: self.keyframes.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        vec![
            ("keyframe_texture", Descriptor::Image(image)),
            ("KeyframeWords", Descriptor::Buffer(self.words.buffer.descriptor())),
            ("KeyframeShape", Descriptor::Buffer(self.shape.descriptor())),
        ]
    }

    /// The keyframe texture as the graph tracks it.
    fn texture(&self) -> Resource {
        Resource::color(self.keyframes.image.raw)
    }
}

impl BladeResponse for KeyframeResponse {
    fn name(&self) -> &'static str {
        match (self.settings.mode, self.per_blade()) {
            (Mode::Uniform, false) => "uniform keyframes",
            (Mode::Uniform, true) => "uniform keyframes per blade",
            (_, false) => "texture keyframes",
            (_, true) => "texture keyframes per blade",
        }
    }

    fn specialize(&self, specialization: &mut Specialization) {
        let s = &self.settings;
        specialization.keyframe_uvec4s = self.words.uvec4s;
        specialization.mode = s.mode.code();
        specialization.smoothing = s.smoothing.code();
        specialization.encoding = match s.mode {
            Mode::Uniform => s.packing.code(),
            _ => s.encoding.code(),
        };
        specialization.representation = match s.representation {
            Representation::Curve => gpu::REPRESENTATION_CURVE,
            Representation::Vertex => gpu::REPRESENTATION_LEVELS,
        };
    }

    fn blade_input(&self) -> BladeInput {
        match self.per_blade() {
            true => BladeInput::PoseRecords,
            false => BladeInput::PerVertex {
                vertex: shaders::BLADE_KEYFRAMES_VERT,
                resources: self.resources(),
                reads: vec![
                    (self.texture(), Access::VertexShaderSampledRead),
                    (Resource::Buffer(self.words.buffer.raw), Access::VertexShaderUniformRead),
                    (Resource::Buffer(self.shape.raw), Access::VertexShaderUniformRead),
                ],
            },
        }
    }

    fn tracked(&self) -> Vec<(Resource, Vec<Access>)> {
        vec![
            (self.texture(), READS.to_vec()),
            (Resource::Buffer(self.words.buffer.raw), UNIFORM_READS.to_vec()),
            (Resource::Buffer(self.shape.raw), UNIFORM_READS.to_vec()),
        ]
    }

    fn passes(&self, device: &Device, setup: &ResponseSetup) -> Result<Vec<Box<dyn Pass>>> {
        if !self.per_blade() {
            return Ok(Vec::new());
        }
        let reads = vec![
            (self.texture(), Access::ComputeShaderSampledRead),
            (Resource::Buffer(self.words.buffer.raw), Access::ComputeShaderUniformRead),
            (Resource::Buffer(self.shape.raw), Access::ComputeShaderUniformRead),
        ];
        let shader = PoseShader {
            name: "blade poses",
            spirv: shaders::BLADE_POSE_COMP.code(device.profile),
            resources: self.resources(),
            uses: reads,
            uniforms: None,
            store: None,
        };
        Ok(vec![Box::new(PosePass::new(device, setup, shader)?)])
    }

    fn tip_offset(&self, wind: Vec3) -> Vec3 {
        // The keyframes' force is the wind over the fixed scale (`wind::KEYFRAME_WIND_SCALE`).
        let (fx, fz) = (wind.x / KEYFRAME_WIND_SCALE, wind.z / KEYFRAME_WIND_SCALE);
        let tip = match self.table.representation {
            Representation::Vertex => {
                *self.table.pose_for(fx, fz, self.settings.smoothing).backbone.last().expect("a root")
            }
            Representation::Curve => self.table.curve_for(fx, fz, self.settings.smoothing).0[3],
        };
        tip - Vec3::Y
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { (self.keyframes, self.words, self.shape).destroy(device) };
    }
}
