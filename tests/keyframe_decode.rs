//! The vertex shader's keyframe decoder (`kf_fetch`), run in a compute shader over the real
//! keyframe texture and uniform array, against the CPU decode of every encoding; and the decoded
//! values against the generated poses, within each encoding's error bound.

#[path = "support/compute.rs"]
mod compute;
#[path = "support/frame_uniforms.rs"]
mod frame_uniforms;
#[path = "support/probes.rs"]
mod probes;

use std::f32::consts::FRAC_PI_2;
use std::sync::Arc;

use ash::vk;
use glam::UVec4;
use meadow::app::{with_device, GpuOptions};
use meadow::keyframes::encoding::{self as enc, Encoding, Packing};
use meadow::keyframes::KeyframeTable;
use meadow::render::animation::{AnimationSettings, KeyframeTexture, KeyframeUniforms};
use meadow::render::uniforms::FrameUniforms;
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::upload::UploadBatch;
use meadow::vk::{pipeline, Buffer, BufferDesc, Device, DeviceSelector};

const SEGMENTS: u32 = 3;

/// Where the shader reads: a texture encoding or a uniform packing.
#[derive(Clone, Copy, Debug)]
enum Source {
    Texture(Encoding),
    Uniform(Packing),
}

impl Source {
    fn code(self) -> u32 {
        match self {
            Source::Texture(e) => e.code(),
            Source::Uniform(p) => p.code(),
        }
    }

    /// CPU decode of one keyframe's four components as stored (twist already divided by π/2).
    fn cpu_decode(self, c: [f32; 4]) -> [f32; 4] {
        match self {
            Source::Texture(Encoding::Float32) => c,
            Source::Texture(Encoding::Unorm16) => c.map(|x| enc::decode_unorm16(enc::encode_unorm16(x))),
            Source::Texture(Encoding::Rgba8x2) => c.map(|x| enc::decode_rgba8x2(enc::e1(x), enc::e2(x))),
            Source::Uniform(Packing::Snorm) => {
                let (a, b) = enc::unpack_snorm2x16(enc::pack_snorm2x16(c[0], c[1]));
                let (d, e) = enc::unpack_snorm2x16(enc::pack_snorm2x16(c[2], c[3]));
                [a, b, d, e]
            }
            Source::Uniform(Packing::Thesis) => {
                let (m0, m1) = (enc::thesis_merge(c[0], c[1]), enc::thesis_merge(c[2], c[3]));
                [enc::thesis_extract1(m0), enc::thesis_extract2(m0), enc::thesis_extract1(m1), enc::thesis_extract2(m1)]
            }
        }
    }

    /// Largest GPU-vs-CPU difference: the thesis' extract1 rounds x·2¹⁶ whose fraction holds the
    /// second value, so ties go either way (GLSL leaves round()'s direction at .5 to the
    /// implementation): one 2⁻¹⁵ step. Every other decode agrees to float precision.
    fn gpu_cpu_tolerance(self) -> f32 {
        match self {
            Source::Uniform(Packing::Thesis) => 3.1e-5,
            _ => 2e-6,
        }
    }

    /// Largest error of a component against the generated value.
    fn bound(self) -> f32 {
        match self {
            Source::Texture(Encoding::Float32) => 2e-7, // the twist's round trip through π/2
            Source::Texture(_) => 3.05175e-5,           // δ16 of thesis 4.4.1
            Source::Uniform(Packing::Snorm) => 1.0 / 32767.0,
            // Measured 3.9e-3 = 2⁻⁸: when the first value is near 1 the merged float is near 2 and
            // keeps only 8 bits of the second. The thesis claims full 16-bit precision.
            Source::Uniform(Packing::Thesis) => 4e-3,
        }
    }
}

fn decode_on_gpu(device: &Arc<Device>, source: Source) -> meadow::Result<(KeyframeTable, Vec<[f32; 4]>)> {
    let settings = AnimationSettings {
        poses: 200,
        encoding: if let Source::Texture(e) = source { e } else { Encoding::Unorm16 },
        ..Default::default()
    };
    let mut batch = UploadBatch::new(device);
    let (texture, table) = KeyframeTexture::new(&mut batch, SEGMENTS, &settings)?;
    let packing = if let Source::Uniform(p) = source { p } else { Packing::Snorm };
    let words = KeyframeUniforms::new(&mut batch, &table, packing)?;
    batch.submit()?;
    let count = table.frames.len();
    let frame = frame_buffer(device)?;
    // The response's uniform block `KeyframeShape`: magnitudes, angles, records per pose.
    let shape = [table.layout.magnitudes, table.layout.angles, SEGMENTS, 0u32];
    let shape =
        Buffer::with_data(device, &BufferDesc::upload("shape", 16, vk::BufferUsageFlags::UNIFORM_BUFFER), &shape)?;
    let out =
        Buffer::new(device, &BufferDesc::readback("decoded", 16 * count as u64, vk::BufferUsageFlags::STORAGE_BUFFER))?;
    let cs = vk::ShaderStageFlags::COMPUTE;
    let bindings = [
        Binding { binding: 0, kind: vk::DescriptorType::UNIFORM_BUFFER, stages: cs },
        Binding { binding: 1, kind: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, stages: cs },
        Binding { binding: 2, kind: vk::DescriptorType::UNIFORM_BUFFER, stages: cs },
        Binding { binding: 3, kind: vk::DescriptorType::UNIFORM_BUFFER, stages: cs },
        Binding { binding: 4, kind: vk::DescriptorType::STORAGE_BUFFER, stages: cs },
    ];
    let set_layout = descriptor::set_layout(device, "decode set layout", &bindings)?;
    let layout = pipeline::layout(device, "decode layout", &[set_layout], &[])?;
    let pipe = pipeline::compute(
        device,
        "keyframe decode",
        probes::KEYFRAME_DECODE_COMP.code(device.profile),
        layout,
        // The uniform array's size, the mode (texture), the encoding or packing.
        &meadow::render::specialization::Specialization {
            keyframe_uvec4s: KeyframeUniforms::capacity(device),
            mode: 1,
            encoding: source.code(),
            ..meadow::render::specialization::Specialization::new(false, 4, 1, false, true)
        }
        .named(),
    )?;
    let (pool, sets) = descriptor::allocate_sets(device, "decode", set_layout, &bindings, 1)?;
    descriptor::write(
        device,
        sets[0],
        &[
            (0, vk::DescriptorType::UNIFORM_BUFFER, Resource::Buffer(frame.descriptor())),
            (
                1,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                Resource::Image(vk::DescriptorImageInfo {
                    sampler: texture.sampler,
                    image_view: texture.image.view,
                    image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }),
            ),
            (2, vk::DescriptorType::UNIFORM_BUFFER, Resource::Buffer(words.buffer.descriptor())),
            (3, vk::DescriptorType::UNIFORM_BUFFER, Resource::Buffer(shape.descriptor())),
            (4, vk::DescriptorType::STORAGE_BUFFER, Resource::Buffer(out.descriptor())),
        ],
    );
    let groups = (count as u32).div_ceil(64);
    let submitted = compute::dispatch(device, "decode", (pipe, layout), &sets, &[], groups, out.raw);
    let decoded = bytemuck::cast_slice::<u8, [f32; 4]>(out.mapped()).to_vec();
    // SAFETY: submit_and_wait waited.
    unsafe {
        compute::teardown(device, (pool, pipe, layout, set_layout), [frame, out, words.buffer, shape]);
        texture.destroy(device);
    }
    submitted.map(|()| (table, decoded))
}

/// The frame uniforms the decode shader reads: the segment count.
fn frame_buffer(device: &Arc<Device>) -> meadow::Result<Buffer> {
    let uniforms = FrameUniforms { params: UVec4::new(SEGMENTS, 0, 0, 0), ..bytemuck::Zeroable::zeroed() };
    frame_uniforms::upload(device, "decode frame", &uniforms)
}

#[test]
fn gpu_decode_of_every_encoding_matches_the_cpu_decode() {
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        for source in [
            Source::Texture(Encoding::Float32),
            Source::Texture(Encoding::Unorm16),
            Source::Texture(Encoding::Rgba8x2),
            Source::Uniform(Packing::Snorm),
            Source::Uniform(Packing::Thesis),
        ] {
            let (table, gpu) = decode_on_gpu(device, source)?;
            let mut worst = 0.0f32;
            for (i, (k, g)) in table.frames.iter().zip(&gpu).enumerate() {
                let stored = [k[0], k[1], k[2], k[3] / FRAC_PI_2];
                let cpu = source.cpu_decode(stored);
                for c in 0..4 {
                    let gpu_value = if c == 3 { g[c] / FRAC_PI_2 } else { g[c] };
                    assert!(
                        (gpu_value - cpu[c]).abs() <= source.gpu_cpu_tolerance(),
                        "{source:?} keyframe {i} component {c}: GPU {gpu_value} CPU {}",
                        cpu[c]
                    );
                    worst = worst.max((gpu_value - stored[c]).abs());
                }
            }
            eprintln!("{source:?}: largest decode error {worst:.3e} (bound {:.3e})", source.bound());
            assert!(worst <= source.bound(), "{source:?}: error {worst} over {}", source.bound());
        }
        Ok(())
    });
    result.expect("decoded");
    assert_eq!(messages, Some(0));
}
