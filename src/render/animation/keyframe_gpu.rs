//! The keyframe table on the GPU (thesis 4.4): as a texture sampled with `texelFetch`
//! (`KeyframeTexture`, 4.4.1) or packed into a uniform array (`KeyframeUniforms`, 4.4.2).

use ash::vk;

use crate::error::{Error, Result};
use crate::keyframes::encoding::{self, Encoding, Packing};
use crate::keyframes::{BladeModel, KeyframeLayout, KeyframeTable, Representation};
use crate::render::animation::AnimationSettings;
use crate::vk::image;
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Destroy, Device, Guard, Image, ImageDesc};

/// The keyframe table on the GPU: one row per stored pose, one texel per level (two for
/// rgba8x2), sampled with `texelFetch` in the vertex shader.
pub struct KeyframeTexture {
    /// The image.
    pub image: Image,
    /// Nearest, clamped sampler (texelFetch ignores filtering; the descriptor needs one).
    pub sampler: vk::Sampler,
    /// Table shape.
    pub layout: KeyframeLayout,
}

/// Vulkan format of an encoding.
pub fn texture_format(encoding: Encoding) -> vk::Format {
    match encoding {
        Encoding::Rgba8x2 => vk::Format::R8G8B8A8_UNORM,
        Encoding::Unorm16 => vk::Format::R16G16B16A16_UNORM,
        Encoding::Float32 => vk::Format::R32G32B32A32_SFLOAT,
    }
}

/// The encoding a keyframe texture can use on `device`: `encoding` when its format can be
/// sampled, else rgba8x2 (R8G8B8A8_UNORM, whose sampling every device supports). The default
/// unorm16 samples R16G16B16A16_UNORM, which the specification does not require.
pub fn sampled_encoding(device: &Device, encoding: Encoding) -> Encoding {
    let features = device.format_features(texture_format(encoding));
    if features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE) {
        encoding
    } else {
        Encoding::Rgba8x2
    }
}

impl KeyframeTexture {
    /// Rows the table for `poses` needs, checked against the device before generating it (and
    /// against the 16-bit row fields of `--eval blade` pose records).
    pub fn check_limits(device: &Device, poses: u32) -> Result<()> {
        let rows = KeyframeLayout::for_poses(poses).stored();
        let max = device.limits().max_image_dimension2_d;
        if rows > max {
            return Err(Error::bad_input(format!(
                "--poses {poses} needs a keyframe texture of {rows} rows, over the device's maxImageDimension2D of {max}"
            )));
        }
        if rows > 65536 {
            return Err(Error::bad_input(format!(
                "--poses {poses} needs {rows} stored poses, more than the 65536 a pose record can index"
            )));
        }
        Ok(())
    }

    /// Generate the table for `segments` and add its upload to `batch`.
    pub fn new(batch: &mut UploadBatch, segments: u32, settings: &AnimationSettings) -> Result<(Self, KeyframeTable)> {
        let device = batch.device();
        let layout = KeyframeLayout::for_poses(settings.poses);
        let table = match settings.representation {
            Representation::Vertex => KeyframeTable::generate(&BladeModel::new(segments), layout),
            Representation::Curve => KeyframeTable::generate_curve(layout),
        };
        let (width, height, texels) = encoding::texture_texels(&table, settings.encoding);
        let desc = ImageDesc::color(
            "keyframe texture",
            texture_format(settings.encoding),
            vk::Extent2D { width, height },
            vk::ImageUsageFlags::SAMPLED,
        );
        // Read by the vertex shader, and by compute passes and tests that decode it.
        let image =
            batch.image(&desc, &texels, &[Access::VertexShaderSampledRead, Access::ComputeShaderSampledRead])?;
        // texelFetch ignores filtering; the combined-image-sampler descriptor still needs one.
        // The upload is not submitted yet: the batch owns only staging.
        let image = Guard::new(device, image);
        let sampler = image::clamped_sampler(device, vk::Filter::NEAREST, "keyframe sampler")?;
        Ok((Self { image: image.take(), sampler, layout }, table))
    }

    /// Free the image and sampler.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            self.image.destroy(device);
        }
    }
}

/// The keyframe table as a uniform array (thesis 4.4.2): `uvec4 keyframe_words[N]` where N, a
/// specialization constant, fills the smaller of `maxUniformBufferRange` and 64 KiB.
pub struct KeyframeUniforms {
    /// The uniform buffer, always `16 N` bytes.
    pub buffer: Buffer,
    /// N.
    pub uvec4s: u32,
}

impl KeyframeUniforms {
    /// `uvec4`s of the uniform array on this device.
    pub fn capacity(device: &Device) -> u32 {
        device.limits().max_uniform_buffer_range.min(65536) / 16
    }

    /// Check that the table for `poses` × `records` fits the uniform array.
    pub fn check_limits(device: &Device, poses: u32, records: u32) -> Result<()> {
        let bytes = u64::from(KeyframeLayout::for_poses(poses).stored()) * u64::from(records) * 8;
        let max = u64::from(device.limits().max_uniform_buffer_range);
        if bytes > 16 * u64::from(Self::capacity(device)) {
            return Err(Error::bad_input(format!(
                "--mode uniform: {poses} poses x {records} records need {bytes} bytes of uniform data, over the device's maxUniformBufferRange of {max} (use --mode texture, or fewer --poses)"
            )));
        }
        Ok(())
    }

    /// Add the upload of `table` packed with `packing` to `batch` (zeros when it does not fit:
    /// only uniform mode reads it, and that mode checked the size first).
    pub fn new(batch: &mut UploadBatch, table: &KeyframeTable, packing: Packing) -> Result<Self> {
        let uvec4s = Self::capacity(batch.device());
        let mut words = encoding::uniform_words(table, packing);
        if words.len() > 4 * uvec4s as usize {
            words.clear();
        }
        words.resize(4 * uvec4s as usize, 0);
        let buffer = batch.buffer(
            "keyframe uniforms",
            &words,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            &[Access::VertexShaderUniformRead, Access::ComputeShaderUniformRead],
        )?;
        Ok(Self { buffer, uvec4s })
    }
}

impl Destroy for KeyframeTexture {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { KeyframeTexture::destroy(self, device) };
    }
}

impl Destroy for KeyframeUniforms {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.buffer.destroy(device) };
    }
}
