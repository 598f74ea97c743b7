//! What animates the blades: the keyframe texture on the GPU, and the per-frame external forces
//! the CPU computes at cluster corners (thesis 3.2.2) and for the point emitters.

use ash::vk;
use glam::{Vec2, Vec4};

use crate::error::{Error, Result};
use crate::keyframes::encoding::{self, Encoding, Packing};
use crate::keyframes::{BladeModel, KeyframeLayout, KeyframeTable, Representation, Smoothing};
use crate::render::gpu_constants;
use crate::scene::clusters::ClusterGrid;
use crate::vk::image;
use crate::vk::upload::UploadBatch;
use crate::vk::{Access, Buffer, Device, Image, ImageDesc};
use crate::wind::{Attenuation, Wind};

/// How blades are posed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Neutral Bézier blades, no forces.
    Static,
    /// Keyframes sampled from a texture in the vertex shader (thesis 4.4.1).
    #[default]
    Texture,
    /// Keyframes in a uniform array, two 16-bit values per 32-bit word (thesis 4.4.2).
    Uniform,
    /// Benchmark floor: the static blades' triangles pre-expanded, transform and flat colour only.
    Floor,
}

impl Mode {
    /// Index used by the shaders.
    pub fn code(self) -> u32 {
        match self {
            Mode::Static => gpu_constants::MODE_STATIC,
            Mode::Texture => gpu_constants::MODE_TEXTURE,
            Mode::Uniform => gpu_constants::MODE_UNIFORM,
            Mode::Floor => gpu_constants::MODE_FLOOR,
        }
    }
}

/// Where the per-blade part of the animation runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Eval {
    /// In the vertex shader, for every vertex (as the thesis did on shader model 3).
    #[default]
    Vertex,
    /// Once per blade in a compute pass that evaluates every level (point, tangent, twist) into
    /// records the vertex shader reads (`shaders/blade_pose.comp`).
    Blade,
}

/// Everything about the animation a renderer is built with.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationSettings {
    /// Static or keyframed.
    pub mode: Mode,
    /// Poses over the full circle (a quarter is stored).
    pub poses: u32,
    /// In-between poses.
    pub smoothing: Smoothing,
    /// Keyframe texture encoding.
    pub encoding: Encoding,
    /// Uniform-array packing.
    pub packing: Packing,
    /// Per vertex or per blade.
    pub eval: Eval,
    /// Vertex levels (thesis) or Bézier control points.
    pub representation: Representation,
    /// Where source magnitudes are attenuated.
    pub attenuation: Attenuation,
    /// Cluster edge in metres.
    pub cluster_size: f32,
    /// The forces.
    pub wind: Wind,
}

impl Default for AnimationSettings {
    fn default() -> Self {
        Self {
            mode: Mode::Texture,
            poses: 1000,
            smoothing: Smoothing::Nearest,
            encoding: Encoding::Unorm16,
            packing: Packing::Snorm,
            eval: Eval::Vertex,
            representation: Representation::Vertex,
            attenuation: Attenuation::Cluster,
            cluster_size: 1.0,
            wind: Wind::default(),
        }
    }
}

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
        let sampler = match image::clamped_sampler(device, vk::Filter::NEAREST, "keyframe sampler") {
            Ok(sampler) => sampler,
            Err(e) => {
                // SAFETY: the upload was not submitted; the batch still owns only staging.
                unsafe { image.destroy(device) };
                return Err(e);
            }
        };
        Ok((Self { image, sampler, layout }, table))
    }

    /// Free the image and sampler.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
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

/// Point sources plus colliders a renderer can hold (the per-frame emitter buffers' capacity).
pub const MAX_EMITTERS: usize = crate::render::gpu_constants::MAX_EMITTERS as usize;

/// The corner forces of a frame: (fx, fz, calm-area exposure, 0) per corner.
pub fn corner_forces(grid: &ClusterGrid, wind: &Wind, time: f32, attenuation: Attenuation) -> Vec<Vec4> {
    (0..grid.corner_count())
        .map(|i| {
            let p = grid.corner_position(i);
            let f = wind.corner_force(p, time, attenuation);
            // A non-finite force (overflowing eq. 4.1) would select an undefined pose: none.
            let f = if f.is_finite() { f } else { Vec2::ZERO };
            Vec4::new(f.x, f.y, wind.exposure(p), 0.0)
        })
        .collect()
}

/// The emitters of a frame: point sources at their positions at `time` as (x, z, power, sigma),
/// then colliders as (centre x, centre z, radius x, radius z). At least one element (a buffer
/// cannot be empty); the shader reads only as many as the uniforms count.
pub fn emitters(wind: &Wind, time: f32) -> Vec<Vec4> {
    let mut out: Vec<Vec4> = wind
        .sources
        .iter()
        .map(|s| {
            let p = s.position_at(time);
            Vec4::new(p.x, p.y, s.power, s.sigma)
        })
        .chain(wind.colliders.iter().map(|c| Vec4::new(c.center.x, c.center.z, c.radii.x, c.radii.z)))
        .collect();
    if out.is_empty() {
        out.push(Vec4::ZERO);
    }
    out
}

/// The force the vertex shader computes for a blade (`shaders/forces.glsl`), on the CPU: the
/// reference for GPU read-back tests.
pub fn blade_force(
    grid: &ClusterGrid,
    cluster: &crate::scene::clusters::BladeCluster,
    corners: &[Vec4],
    emitters: &[Vec4],
    sources: usize,
    attenuation: Attenuation,
    root: Vec2,
) -> Vec2 {
    let n = grid.corners_per_side() as usize;
    let w = cluster.unpacked_weights();
    let c = cluster.corner as usize;
    let f = corners[c] * w[0] + corners[c + 1] * w[1] + corners[c + n] * w[2] + corners[c + n + 1] * w[3];
    let mut force = Vec2::new(f.x, f.y);
    if attenuation == Attenuation::Blade {
        for e in &emitters[..sources] {
            force += f.z * crate::wind::PointSource::force_from(Vec2::new(e.x, e.y), e.z, e.w, root);
        }
        for e in &emitters[sources..] {
            force += crate::wind::Collider::force(Vec2::new(e.x, e.y), Vec2::new(e.z, e.w), root);
        }
    }
    force
}
