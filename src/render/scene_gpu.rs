//! The scene on the GPU: blade storage buffer, terrain heights, cluster records, the blade alpha
//! texture and its sampler, uploaded once through staging; and set `SET_SCENE` that every scene
//! pass binds (the scene and one frame's uniforms and forces). What animates the blades is the
//! animation model's (`render::animation::model`).

use ash::vk;

use crate::error::Result;
use crate::render::frame::Frame;
use crate::render::gpu_constants;
use crate::scene::clusters::{BladeCluster, ClusterGrid};
use crate::scene::{alpha, Scene};
use crate::vk::descriptor::{self, Binding, Resource};
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Device, Image, ImageDesc};

/// Bytes of the `--eval blade` pose records: `segments + 1` records of `POSE_WORDS` words per
/// blade (`shaders/bindings.glsl`).
pub fn pose_bytes(blades: u32, segments: u32) -> u64 {
    4 * u64::from(gpu_constants::POSE_WORDS) * u64::from(blades.max(1)) * u64::from(segments + 1)
}

/// Binding numbers of set 0, generated from `shaders/shared.glsl` (`BINDING_*`).
pub mod binding {
    use crate::render::gpu_constants as gpu;

    /// `FrameUniforms` uniform buffer.
    pub const FRAME: u32 = gpu::BINDING_FRAME;
    /// `BladeInstance[]` storage buffer.
    pub const BLADES: u32 = gpu::BINDING_BLADES;
    /// Terrain heights storage buffer.
    pub const HEIGHTS: u32 = gpu::BINDING_HEIGHTS;
    /// Blade alpha texture.
    pub const BLADE_ALPHA: u32 = gpu::BINDING_BLADE_ALPHA;
    /// `BladeCluster[]` storage buffer.
    pub const CLUSTERS: u32 = gpu::BINDING_CLUSTERS;
    /// Per-frame corner forces.
    pub const CORNERS: u32 = gpu::BINDING_CORNERS;
    /// Per-frame point sources and colliders.
    pub const EMITTERS: u32 = gpu::BINDING_EMITTERS;
}

/// Layout of set `SET_SCENE`, shared by the scene passes and the animation's compute passes.
pub fn bindings() -> [Binding; 7] {
    let vs = vk::ShaderStageFlags::VERTEX;
    let vs_cs = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::COMPUTE;
    let all = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
    let uniform = vk::DescriptorType::UNIFORM_BUFFER;
    [
        Binding { binding: binding::FRAME, kind: uniform, stages: all },
        Binding { binding: binding::BLADES, kind: storage, stages: vs_cs },
        Binding { binding: binding::HEIGHTS, kind: storage, stages: vs },
        Binding { binding: binding::BLADE_ALPHA, kind: sampled, stages: vk::ShaderStageFlags::FRAGMENT },
        Binding { binding: binding::CLUSTERS, kind: storage, stages: vs_cs },
        Binding { binding: binding::CORNERS, kind: storage, stages: vs_cs },
        Binding { binding: binding::EMITTERS, kind: storage, stages: vs_cs },
    ]
}

/// Device-local copies of the scene and of its animation data.
pub struct SceneGpu {
    /// One `BladeInstance` per blade.
    pub blades: Buffer,
    /// Number of blades in `blades`.
    pub blade_count: u32,
    /// `(cells + 1)²` terrain heights.
    pub heights: Buffer,
    /// Terrain cells per side.
    pub terrain_cells: u32,
    /// Terrain grid origin and cell size.
    pub terrain_origin: f32,
    /// Cell edge in metres.
    pub terrain_cell_size: f32,
    /// The blade outline (R8).
    pub blade_alpha: Image,
    /// Linear, clamped sampler for the alpha texture.
    pub sampler: vk::Sampler,
    /// One `BladeCluster` per blade.
    pub clusters: Buffer,
    /// The cluster grid the records refer to.
    pub grid: ClusterGrid,
}

/// Resources created so far by `upload`, freed if it fails half-way.
#[derive(Default)]
struct Partial {
    blades: Option<Buffer>,
    heights: Option<Buffer>,
    clusters: Option<Buffer>,
    blade_alpha: Option<Image>,
}

impl Partial {
    /// # Safety
    /// No pending work may use the resources.
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for buffer in [self.blades, self.heights, self.clusters].into_iter().flatten() {
                buffer.destroy(device);
            }
            if let Some(image) = self.blade_alpha {
                image.destroy(device);
            }
        }
    }
}

impl SceneGpu {
    /// Bytes of device memory `upload` will allocate for `scene` (staging included, as it
    /// coexists with the destination during the upload).
    pub fn memory_bytes(blade_count: u64, terrain_cells: u64) -> u64 {
        // Blade record, cluster record, pose record (with --eval blade).
        let blades = blade_count
            * (std::mem::size_of::<crate::scene::BladeInstance>() + std::mem::size_of::<BladeCluster>() + 16) as u64;
        let heights = (terrain_cells + 1).pow(2) * 4;
        let alpha = u64::from(alpha::WIDTH * alpha::HEIGHT);
        2 * (blades + heights + alpha)
    }

    /// Upload the scene and its cluster records (clusters of about `cluster_size` metres) in one
    /// batch.
    pub fn upload(device: &Device, scene: &Scene, cluster_size: f32) -> Result<Self> {
        let mut partial = Partial::default();
        let grid = ClusterGrid::new(scene.terrain.size, cluster_size);
        let result = Self::upload_into(device, scene, &grid, &mut partial);
        match result {
            Ok(sampler) => Ok(Self {
                blades: partial.blades.take().expect("uploaded"),
                blade_count: scene.blades.len() as u32,
                heights: partial.heights.take().expect("uploaded"),
                terrain_cells: scene.terrain.cells,
                terrain_origin: scene.terrain.origin(),
                terrain_cell_size: scene.terrain.cell_size(),
                blade_alpha: partial.blade_alpha.take().expect("uploaded"),
                sampler,
                clusters: partial.clusters.take().expect("uploaded"),
                grid,
            }),
            Err(e) => {
                // SAFETY: the batch waited for its submission or never submitted.
                unsafe { partial.destroy(device) };
                Err(e)
            }
        }
    }

    fn upload_into(device: &Device, scene: &Scene, grid: &ClusterGrid, partial: &mut Partial) -> Result<vk::Sampler> {
        let mut batch = UploadBatch::new(device);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let vertex_read: &'static [Access] = &[Access::VertexShaderStorageRead];
        // Blades and clusters are also read by the blade-pose compute pass.
        let vertex_compute_read: &'static [Access] = &[Access::VertexShaderStorageRead, Access::ComputeShaderRead];
        partial.blades = Some(batch.buffer("blades", &scene.blades, storage, vertex_compute_read)?);
        partial.heights = Some(batch.buffer("terrain heights", &scene.terrain.heights, storage, vertex_read)?);
        let clusters = grid.assign(&scene.blades);
        partial.clusters = Some(batch.buffer("blade clusters", &clusters, storage, vertex_compute_read)?);
        let desc = ImageDesc::color(
            "blade alpha",
            vk::Format::R8_UNORM,
            vk::Extent2D { width: alpha::WIDTH, height: alpha::HEIGHT },
            vk::ImageUsageFlags::SAMPLED,
        );
        partial.blade_alpha = Some(batch.image(&desc, &alpha::texels(), &[Access::FragmentShaderSampledRead])?);
        batch.submit()?;
        let sampler = crate::vk::image::clamped_sampler(device, vk::Filter::LINEAR, "blade alpha sampler")?;
        Ok(sampler)
    }

    /// Point `set` at the scene resources and at one frame's uniforms, corners and emitters.
    pub fn write_descriptors(&self, device: &Device, set: vk::DescriptorSet, frame: &Frame) {
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let image = |sampler, image_view| {
            Resource::Image(vk::DescriptorImageInfo {
                sampler,
                image_view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            })
        };
        descriptor::write(
            device,
            set,
            &[
                (binding::FRAME, vk::DescriptorType::UNIFORM_BUFFER, Resource::Buffer(frame.uniforms.descriptor())),
                (binding::BLADES, storage, Resource::Buffer(self.blades.descriptor())),
                (binding::HEIGHTS, storage, Resource::Buffer(self.heights.descriptor())),
                (binding::BLADE_ALPHA, sampled, image(self.sampler, self.blade_alpha.view)),
                (binding::CLUSTERS, storage, Resource::Buffer(self.clusters.descriptor())),
                (binding::CORNERS, storage, Resource::Buffer(frame.corners.descriptor())),
                (binding::EMITTERS, storage, Resource::Buffer(frame.emitters.descriptor())),
            ],
        );
    }

    /// Free everything.
    ///
    /// # Safety
    /// No pending GPU work may use the scene.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            device.raw.destroy_sampler(self.sampler, None);
            self.clusters.destroy(device);
            self.blade_alpha.destroy(device);
            self.heights.destroy(device);
            self.blades.destroy(device);
        }
    }
}
