//! The seam every animation model plugs into. A model owns its GPU resources (descriptor set
//! `SET_ANIMATION`: a keyframe texture, a keyframe uniform array, pose records), sets its
//! specialization constants and its part of the frame uniforms, adds its compute passes to the
//! graph (the wind it reads is the wind field's, `render::wind`), and tells the blade pass how to pose a blade: through
//! the model's own per-vertex shader path (the thesis' per-vertex keyframe evaluation, kept for
//! the benchmark), or from pose records its passes wrote (the `--eval blade` format, the path
//! physics and wind-field models write into).
//!
//! Models today: `still::StaticModel` and `keyframed::KeyframeModel` (texture or uniform array,
//! per vertex or per blade).

use crate::error::Result;
use crate::render::animation::{KeyframeTexture, KeyframeUniforms};
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::scene_gpu::SceneGpu;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::{Resource as Descriptor, SetLayout};
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, BufferDesc, Destroy, Device, Guard, Resource, TexelView};
use ash::vk;

/// How the blade pass poses a blade.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BladeInput {
    /// The model's per-vertex path in `blade.vert`, chosen by its specialization constants.
    PerVertex,
    /// Pose records (`POSE_WORDS` words per level, written by the model's passes before the
    /// blade pass), and the buffer of placed levels the cull's path turns them into.
    PoseRecords(vk::Buffer, vk::Buffer),
}

/// What a model's compute passes are built with.
pub struct PassSetup<'a> {
    /// The scene pipeline layout (sets `SET_SCENE` and `SET_ANIMATION`).
    pub layout: vk::PipelineLayout,
    /// Those sets' layouts, for a pass with a set of its own (`recording::PassSet`).
    pub sets: crate::render::recording::SceneSets<'a>,
    /// The specialization constants of the scene pipelines.
    pub constants: &'a Specialization,
    /// The scene on the GPU.
    pub scene: &'a SceneGpu,
    /// Each frame's wind at the cluster corners (set 0's `Corners`, by frame slot), which the
    /// wind field's pass writes: a pass whose shaders sample the wind declares its read of
    /// `wind[ctx.slot]`, so the graph orders it after that write.
    pub wind: &'a [vk::Buffer],
    /// With the cull before the blade pass, the segments of its LOD buckets: a model's per-blade
    /// pass then covers only its visible list, bucket by bucket (`render::recording::bucket_dispatch`), and is
    /// added after the cull's passes. `None` without the cull.
    pub buckets: Option<&'a [u32]>,
}

/// An animation model.
pub trait AnimationModel {
    /// Name in reports.
    fn name(&self) -> &'static str;

    /// Set the constants that choose the model's shader path (mode, smoothing, encoding,
    /// attenuation, representation, `FLAG_EVAL_BLADE`, the uniform array's size).
    fn specialize(&self, specialization: &mut Specialization);

    /// Fill the model's part of the frame uniforms (the keyframe table's shape).
    fn fill_uniforms(&self, uniforms: &mut FrameUniforms);

    /// The model's resources: set `SET_ANIMATION`.
    fn resources(&self) -> &AnimationSet;

    /// How the blade pass poses a blade.
    fn blade_input(&self) -> BladeInput;

    /// The compute passes that run before the blade pass.
    fn passes(&self, device: &Device, setup: &PassSetup) -> Result<Vec<Box<dyn Pass>>>;

    /// Destroy the model's resources.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    unsafe fn destroy(self: Box<Self>, device: &Device);
}

/// The wind's part of one frame in flight (`frame::PerFrame`), read through set 0: the wind
/// field at the cluster corners, written by the analytic field's pass on the GPU with the cull and
/// by the CPU before each submission with `--brute-force` (the thesis' path, 3.2.2), and the point
/// sources and colliders at the frame's time, written by the CPU (`render::wind::WindField`).
pub struct FrameForces {
    /// Host-visible wind at the cluster corners: velocity (x, y, z) in m/s and exposure.
    pub corners: Buffer,
    /// Host-visible point sources and colliders at the frame's time, relative to O.
    pub emitters: Buffer,
}

impl FrameForces {
    /// Set 0's resources of this frame, by the names `shaders/animation/frame_forces.glsl`
    /// declares them with (build.rs numbers them).
    pub fn scene_resources(&self) -> [(&'static str, Descriptor); 2] {
        [
            ("Corners", Descriptor::Buffer(self.corners.descriptor())),
            ("Emitters", Descriptor::Buffer(self.emitters.descriptor())),
        ]
    }

    /// The forces of frame `slot`: room for `corners` corner forces and `emitters` emitters.
    pub fn new(device: &Device, slot: usize, corners: u32, emitters: u32) -> Result<Self> {
        let vec4 = 16u64;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let buffer = |name: &str, count: u32, usage| {
            let name = format!("frame {slot} {name}");
            Buffer::new(device, &BufferDesc::upload(&name, vec4 * u64::from(count.max(1)), storage | usage))
        };
        // The corners are read back by tests (`Renderer::read_wind_corners`).
        let corners = Guard::new(device, buffer("wind corners", corners, vk::BufferUsageFlags::TRANSFER_SRC)?);
        let emitters = buffer("emitters", emitters, vk::BufferUsageFlags::empty())?;
        Ok(Self { corners: corners.take(), emitters })
    }
}

impl Destroy for FrameForces {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { (self.corners, self.emitters).destroy(device) };
    }
}

/// Pose records and, with the cull, the drawn blades' placed levels: the two per-blade buffers of
/// a model that evaluates once per blade (`--eval blade`).
pub struct PerBlade {
    /// Pose records.
    pub poses: Buffer,
    /// Placed, lit levels (`passes::BladeLevelsPass`), as many records as `level_records`.
    pub levels: Buffer,
    /// The placed levels as RG32UI texels, as blade.vert fetches them.
    pub level_texels: TexelView,
    /// Records `levels` holds.
    pub level_records: u32,
}

impl PerBlade {
    /// Room for `records` pose records and `levels` placed levels of `segments` segments, as
    /// many as one storage buffer holds (a stand-in of one level for a count of 0).
    pub fn new(device: &Device, (records, levels): (u32, u32), segments: u32) -> Result<Self> {
        use crate::render::scene_gpu::{level_bytes, level_records, pose_bytes};
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let pose_size = match records {
            0 => 4 * u64::from(gpu::POSE_WORDS),
            _ => pose_bytes(records, segments),
        };
        let level_records = level_records(device, levels, segments);
        let level_size = match level_records {
            0 => 8 * u64::from(gpu::LEVEL_UVEC2S),
            _ => level_bytes(level_records, segments),
        };
        let poses = Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("blade poses", pose_size, usage))?);
        let level_usage = usage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let levels = BufferDesc::gpu_only("blade levels", level_size, level_usage);
        let levels = Guard::new(device, Buffer::new(device, &levels)?);
        let level_texels = TexelView::new(device, &levels, vk::Format::R32G32_UINT, "blade level texels")?;
        Ok(Self { poses: poses.take(), levels: levels.take(), level_texels, level_records })
    }
}

impl Destroy for PerBlade {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.poses.destroy(device);
            self.level_texels.destroy(device);
            self.levels.destroy(device);
        }
    }
}

impl Destroy for AnimationSet {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { AnimationSet::destroy(self, device) };
    }
}

/// A model's resources, bound as set `SET_ANIMATION`: the keyframe table as a texture and as a
/// uniform array, the pose records and the drawn blades' placed levels.
pub struct AnimationSet {
    /// The keyframe texture (a 1×1 stand-in for models without keyframes).
    pub keyframes: KeyframeTexture,
    /// The keyframe uniform array (a stand-in of one `uvec4` for models without keyframes).
    pub words: KeyframeUniforms,
    /// Pose records and placed levels (stand-ins of one level without `--eval blade`).
    pub per_blade: PerBlade,
    pool: vk::DescriptorPool,
    /// The set.
    pub set: vk::DescriptorSet,
}

impl AnimationSet {
    /// Allocate the set and point it at the model's resources (destroyed with the set on failure).
    pub fn new(
        device: &Device,
        set_layout: &SetLayout,
        keyframes: KeyframeTexture,
        words: KeyframeUniforms,
        per_blade: PerBlade,
    ) -> Result<Self> {
        let parts = Guard::new(device, (keyframes, words, per_blade));
        let (pool, sets) = set_layout.allocate(device, "animation set", 1)?;
        let (keyframes, words, per_blade) = parts.take();
        let resources = Guard::new(device, Self { keyframes, words, per_blade, pool, set: sets[0] });
        let image = vk::DescriptorImageInfo {
            sampler: resources.keyframes.sampler,
            image_view: resources.keyframes.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        };
        // Every resource by its binding; the layout (reflected from the scene shaders) writes
        // those its shaders bind.
        set_layout.write(
            device,
            resources.set,
            "animation set",
            &[
                (gpu::BINDING_KEYFRAMES, Descriptor::Image(image)),
                (gpu::BINDING_KEYFRAME_WORDS, Descriptor::Buffer(resources.words.buffer.descriptor())),
                (gpu::BINDING_POSES, Descriptor::Buffer(resources.per_blade.poses.descriptor())),
                (gpu::BINDING_LEVELS, Descriptor::Buffer(resources.per_blade.levels.descriptor())),
                (gpu::BINDING_LEVEL_TEXELS, Descriptor::Texels(resources.per_blade.level_texels.raw)),
            ],
        )?;
        Ok(resources.take())
    }

    /// Submit `batch` (the uploads of `keyframes` and `words`), create room for `room` pose
    /// records and placed levels of `segments` segments (`PerBlade::new`) and fill the set;
    /// everything is freed if a step fails.
    pub fn upload(
        device: &Device,
        set_layout: &SetLayout,
        batch: UploadBatch,
        keyframes: KeyframeTexture,
        words: KeyframeUniforms,
        (room, segments): ((u32, u32), u32),
    ) -> Result<Self> {
        // The batch waits for its submission, or never submits.
        let uploaded = Guard::new(device, (keyframes, words));
        batch.submit()?;
        let per_blade = PerBlade::new(device, room, segments)?;
        let (keyframes, words) = uploaded.take();
        Self::new(device, set_layout, keyframes, words, per_blade)
    }

    /// The keyframe texture as the graph tracks it, with the accesses its upload left.
    pub fn keyframe_import(&self) -> (Resource, [Access; 2]) {
        (Resource::color(self.keyframes.image.raw), [Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead])
    }

    /// Destroy the resources and the set's pool.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            self.keyframes.destroy(device);
            self.words.buffer.destroy(device);
            self.per_blade.destroy(device);
        }
    }
}
