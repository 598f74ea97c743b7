//! The scene on the GPU: blade storage buffer, terrain heights, the blade alpha texture and its
//! sampler, uploaded once through staging. Also the descriptor bindings the scene passes share.

use ash::vk;

use crate::error::{Result, VkContext};
use crate::scene::{alpha, Scene};
use crate::vk::descriptor::{self, Binding, Resource};
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Device, Image, ImageDesc};

/// Binding numbers of set 0 (`shaders/common.glsl`).
pub mod binding {
    /// `FrameUniforms` uniform buffer.
    pub const FRAME: u32 = 0;
    /// `BladeInstance[]` storage buffer.
    pub const BLADES: u32 = 1;
    /// Terrain heights storage buffer.
    pub const HEIGHTS: u32 = 2;
    /// Blade alpha texture.
    pub const BLADE_ALPHA: u32 = 3;
}

/// Layout of set 0 shared by the scene passes.
pub fn bindings() -> [Binding; 4] {
    let vs_fs = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    [
        Binding {
            binding: binding::FRAME,
            kind: vk::DescriptorType::UNIFORM_BUFFER,
            stages: vs_fs,
        },
        Binding {
            binding: binding::BLADES,
            kind: vk::DescriptorType::STORAGE_BUFFER,
            stages: vk::ShaderStageFlags::VERTEX,
        },
        Binding {
            binding: binding::HEIGHTS,
            kind: vk::DescriptorType::STORAGE_BUFFER,
            stages: vk::ShaderStageFlags::VERTEX,
        },
        Binding {
            binding: binding::BLADE_ALPHA,
            kind: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            stages: vk::ShaderStageFlags::FRAGMENT,
        },
    ]
}

/// Device-local copies of the scene.
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
}

impl SceneGpu {
    /// Bytes of device memory `upload` will allocate for `scene` (staging included, as it
    /// coexists with the destination during the upload).
    pub fn memory_bytes(blade_count: u64, terrain_cells: u64) -> u64 {
        let blades = blade_count * std::mem::size_of::<crate::scene::BladeInstance>() as u64;
        let heights = (terrain_cells + 1).pow(2) * 4;
        let alpha = u64::from(alpha::WIDTH * alpha::HEIGHT);
        2 * (blades + heights + alpha)
    }

    /// Upload the scene in one batch.
    pub fn upload(device: &Device, scene: &Scene) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let blades = batch.buffer(
            "blades",
            &scene.blades,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &[Access::VertexShaderStorageRead],
        )?;
        let rest = (|| {
            let heights = batch.buffer(
                "terrain heights",
                &scene.terrain.heights,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                &[Access::VertexShaderStorageRead],
            )?;
            let desc = ImageDesc::color(
                "blade alpha",
                vk::Format::R8_UNORM,
                vk::Extent2D {
                    width: alpha::WIDTH,
                    height: alpha::HEIGHT,
                },
                vk::ImageUsageFlags::SAMPLED,
            );
            let blade_alpha = match batch.image(&desc, &alpha::texels(), &[Access::FragmentShaderSampledRead]) {
                Ok(image) => image,
                Err(e) => {
                    // SAFETY: never used by the GPU.
                    unsafe { heights.destroy(device) };
                    return Err(e);
                }
            };
            Ok((heights, blade_alpha))
        })();
        let (heights, blade_alpha) = match rest {
            Ok(rest) => rest,
            Err(e) => {
                // SAFETY: never used by the GPU.
                unsafe { blades.destroy(device) };
                return Err(e);
            }
        };
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        let submitted = batch.submit().and_then(|()| {
            // SAFETY: valid create info.
            unsafe { device.raw.create_sampler(&sampler_info, None) }.vk("vkCreateSampler")
        });
        let sampler = match submitted {
            Ok(sampler) => sampler,
            Err(e) => {
                // SAFETY: the batch waited (or the device is idle).
                unsafe {
                    blades.destroy(device);
                    heights.destroy(device);
                    blade_alpha.destroy(device);
                }
                return Err(e);
            }
        };
        device.set_name(sampler, "blade alpha sampler");
        Ok(Self {
            blades,
            blade_count: scene.blades.len() as u32,
            heights,
            terrain_cells: scene.terrain.cells,
            terrain_origin: scene.terrain.origin(),
            terrain_cell_size: scene.terrain.cell_size(),
            blade_alpha,
            sampler,
        })
    }

    /// Point `set` at the scene resources and at `uniforms`.
    pub fn write_descriptors(&self, device: &Device, set: vk::DescriptorSet, uniforms: &Buffer) {
        descriptor::write(
            device,
            set,
            &[
                (
                    binding::FRAME,
                    vk::DescriptorType::UNIFORM_BUFFER,
                    Resource::Buffer(uniforms.descriptor()),
                ),
                (
                    binding::BLADES,
                    vk::DescriptorType::STORAGE_BUFFER,
                    Resource::Buffer(self.blades.descriptor()),
                ),
                (
                    binding::HEIGHTS,
                    vk::DescriptorType::STORAGE_BUFFER,
                    Resource::Buffer(self.heights.descriptor()),
                ),
                (
                    binding::BLADE_ALPHA,
                    vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    Resource::Image(vk::DescriptorImageInfo {
                        sampler: self.sampler,
                        image_view: self.blade_alpha.view,
                        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    }),
                ),
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
            self.blade_alpha.destroy(device);
            self.heights.destroy(device);
            self.blades.destroy(device);
        }
    }
}
