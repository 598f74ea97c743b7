//! GPU tests of the shared data layout and of the validation harness itself.

#[path = "support/compute.rs"]
mod compute;
#[path = "support/probes.rs"]
mod probes;

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, UVec4, Vec4};
use meadow::app::{with_device, GpuOptions};
use meadow::render::gpu_constants as gpu;
use meadow::render::specialization::{self, Specialization};
use meadow::render::uniforms::FrameUniforms;
use meadow::scene::{BladeInstance, Scene};
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::{pipeline, Buffer, BufferDesc, Device, DeviceSelector};

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") }
}

/// Run `spirv` once over `groups` workgroups with `input` at binding 0 (of `kind`) and a
/// `words`-word storage buffer at binding 1, and return that buffer.
fn run_compute(
    device: &Arc<Device>,
    spirv: &[u8],
    constants: &[(&str, u32)],
    (kind, input): (vk::DescriptorType, &[u8]),
    words: usize,
    groups: u32,
) -> meadow::Result<Vec<u32>> {
    let usage = match kind {
        vk::DescriptorType::UNIFORM_BUFFER => vk::BufferUsageFlags::UNIFORM_BUFFER,
        _ => vk::BufferUsageFlags::STORAGE_BUFFER,
    };
    let input = Buffer::with_data(device, &BufferDesc::upload("test input", input.len() as u64, usage), input)?;
    let output = Buffer::new(
        device,
        &BufferDesc::readback("test fields", 4 * words as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
    )?;
    let bindings = [
        Binding { binding: 0, kind, stages: vk::ShaderStageFlags::COMPUTE },
        Binding { binding: 1, kind: vk::DescriptorType::STORAGE_BUFFER, stages: vk::ShaderStageFlags::COMPUTE },
    ];
    let set_layout = descriptor::set_layout(device, "readback set layout", &bindings)?;
    let layout = pipeline::layout(device, "readback layout", &[set_layout], &[])?;
    let pipe = pipeline::compute(device, "readback", spirv, layout, constants)?;
    let (pool, sets) = descriptor::allocate_sets(device, "readback", set_layout, &bindings, 1)?;
    descriptor::write(
        device,
        sets[0],
        &[
            (0, kind, Resource::Buffer(input.descriptor())),
            (1, vk::DescriptorType::STORAGE_BUFFER, Resource::Buffer(output.descriptor())),
        ],
    );
    let submitted = compute::dispatch(device, "readback", (pipe, layout), &sets, &[], groups, output.raw);
    let words = bytemuck::cast_slice::<u8, u32>(output.mapped()).to_vec();
    // SAFETY: submit_and_wait waited for the dispatch.
    unsafe { compute::teardown(device, (pool, pipe, layout, set_layout), [input, output]) };
    submitted.map(|()| words)
}

/// Write `blades` from Rust, read every field back through `blade_readback.comp`.
fn read_back(device: &Arc<Device>, blades: &[BladeInstance]) -> meadow::Result<Vec<u32>> {
    let input = (vk::DescriptorType::STORAGE_BUFFER, bytemuck::cast_slice(blades));
    let groups = (blades.len() as u32).div_ceil(64);
    run_compute(device, probes::BLADE_READBACK_COMP.code(device.profile), &[], input, 8 * blades.len(), groups)
}

#[test]
fn every_blade_field_reads_back_through_a_compute_shader() {
    let mut blades = Scene::generate(1000, 99).blades;
    // Distinctive values in every field, including all variation bytes.
    blades[0] = BladeInstance {
        position: [1.5, -2.25, 3.125],
        facing: 6.0,
        height: 0.5,
        width: 0.0125,
        stiffness: 1.25,
        variation: 0xa1b2_c3d4,
    };
    let (result, messages) = with_device(&options(), false, |device| read_back(device, &blades));
    let words = result.expect("readback ran");
    assert_eq!(messages, Some(0), "validation messages");
    assert_eq!(words.len(), 8 * blades.len());
    for (i, blade) in blades.iter().enumerate() {
        let expected: [u32; 8] = bytemuck::cast(*blade);
        assert_eq!(&words[8 * i..8 * i + 8], &expected, "blade {i}");
    }
}

/// Words `frame_readback.comp` writes: the uniforms, one per specialization-constant id, six
/// shared constants.
const FRAME_WORDS: usize = 248;
const READBACK_WORDS: usize = FRAME_WORDS + specialization::COUNT + 6;

#[test]
fn every_frame_uniform_and_specialization_constant_reads_back_through_a_compute_shader() {
    // Distinct values in every field (no two words alike), so a swapped or shifted field shows.
    let f = |i: u32| 1.0 + i as f32 * 0.125;
    let uniforms = FrameUniforms {
        view_proj: Mat4::from_cols_array(&std::array::from_fn(|i| f(i as u32))),
        camera_position: Vec4::new(f(16), f(17), f(18), f(19)),
        sun_direction: Vec4::new(f(20), f(21), f(22), f(23)),
        sky_color: Vec4::new(f(24), f(25), f(26), f(27)),
        terrain: Vec4::new(f(28), f(29), f(30), f(31)),
        params: UVec4::new(1001, 1002, 1003, 1004),
        wind_counts: UVec4::new(1005, 1006, 1007, 1008),
        cull_view_proj: Mat4::from_cols_array(&std::array::from_fn(|i| f(32 + i as u32))),
        cull_eye: Vec4::new(f(48), f(49), f(50), f(51)),
        lod: Vec4::new(f(52), f(53), f(54), f(55)),
        tile_grid: Vec4::new(f(56), f(57), f(58), f(59)),
        cull_tiles: UVec4::new(1013, 1014, 1015, 1016),
        cull_lod: UVec4::new(1017, 1018, 1019, 1020),
        relief_waves: std::array::from_fn(|i| Vec4::splat(f(60 + i as u32)) + Vec4::new(0.0, 0.01, 0.02, 0.03)),
        relief_phases: std::array::from_fn(|i| Vec4::splat(f(70 + i as u32)) + Vec4::new(0.0, 0.01, 0.02, 0.03)),
        field_cells: glam::IVec4::new(-1021, 1022, -1023, 1024),
        field: Vec4::new(f(80), f(81), f(82), f(83)),
        ground: UVec4::new(1025, 1026, 1027, 1028),
        relief_cycles: std::array::from_fn(|i| {
            glam::IVec4::new(-2000, 2001, -2002, 2003) + glam::IVec4::splat(10 * i as i32)
        }),
        ground_levels: std::array::from_fn(|i| Vec4::splat(f(90 + i as u32)) + Vec4::new(0.0, 0.01, 0.02, 0.03)),
        ground_windows: std::array::from_fn(|i| {
            glam::IVec4::new(3000, -3001, 3002, -3003) + glam::IVec4::splat(10 * i as i32)
        }),
        cull_classes: UVec4::new(4001, 4002, 4003, 4004),
        cull_class_first: UVec4::new(4005, 4006, 4007, 4008),
        cull_bucket_draws: std::array::from_fn(|i| UVec4::new(5000, 5001, 5002, 5003) + UVec4::splat(10 * i as u32)),
        band_eye: Vec4::new(f(100), f(101), f(102), f(103)),
        cull_room: UVec4::new(6001, 6002, 6003, 6004),
    };
    let spec = Specialization {
        keyframe_uvec4s: 2000,
        mode: 2001,
        smoothing: 2002,
        encoding: 2003,
        attenuation: 2004,
        representation: 2005,
        flags: 2006,
        segments: 2007,
        blades_per_instance: 2008,
        encode_srgb: 2009,
        model_segments: 2010,
        cull_group: 2011,
        msaa_samples: 2012,
        strip_area: 1.25f32.to_bits(),
        strip_l6: 0.75f32.to_bits(),
        tile_rows_capacity: 2013,
        lod_bucket: 2014,
        ground_cells: 2015,
        ground_levels: 2016,
        ground_cover: 2017,
        clump_size_mm: 2027,
        flower_share: 0.05f32.to_bits(),
    };
    let input = (vk::DescriptorType::UNIFORM_BUFFER, bytemuck::bytes_of(&uniforms));
    let (result, messages) = with_device(&options(), false, |device| {
        run_compute(device, probes::FRAME_READBACK_COMP.code(device.profile), &spec.named(), input, READBACK_WORDS, 1)
    });
    let words = result.expect("readback ran");
    assert_eq!(messages, Some(0), "validation messages");
    let expected: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&uniforms));
    assert_eq!(expected.len(), FRAME_WORDS);
    assert_eq!(&words[..FRAME_WORDS], expected, "FrameUniforms");
    // Each named constant of the shaders holds the Specialization field of the same name; the
    // probe writes each at its id, build.rs's, reflected from the SPIR-V.
    let code = probes::FRAME_READBACK_COMP.code(meadow::vk::profile::Profile::Lavapipe);
    let ids = meadow::vk::reflect::spec_constants("frame_readback.comp", code).expect("reflected");
    assert_eq!(ids.len(), specialization::COUNT, "{ids:?}");
    let seen = |name: &str| {
        let id = ids.iter().find(|(_, n)| n == name).unwrap_or_else(|| panic!("{name} in {ids:?}")).0;
        words[FRAME_WORDS + id as usize]
    };
    assert_eq!(seen("KEYFRAME_UVEC4S"), spec.keyframe_uvec4s, "KEYFRAME_UVEC4S");
    assert_eq!(seen("ANIMATION_MODE"), spec.mode, "ANIMATION_MODE");
    assert_eq!(seen("SMOOTHING"), spec.smoothing, "SMOOTHING");
    assert_eq!(seen("KEYFRAME_ENCODING"), spec.encoding, "KEYFRAME_ENCODING");
    assert_eq!(seen("ATTENUATION"), spec.attenuation, "ATTENUATION");
    assert_eq!(seen("REPRESENTATION"), spec.representation, "REPRESENTATION");
    assert_eq!(seen("RENDER_FLAGS"), spec.flags, "RENDER_FLAGS");
    assert_eq!(seen("SEGMENTS"), spec.segments, "SEGMENTS");
    assert_eq!(seen("BLADES_PER_INSTANCE"), spec.blades_per_instance, "BLADES_PER_INSTANCE");
    assert_eq!(seen("ENCODE_SRGB"), spec.encode_srgb, "ENCODE_SRGB");
    assert_eq!(seen("MODEL_SEGMENTS"), spec.model_segments, "MODEL_SEGMENTS");
    assert_eq!(seen("CULL_GROUP"), spec.cull_group, "CULL_GROUP");
    assert_eq!(seen("MSAA_SAMPLES"), spec.msaa_samples, "MSAA_SAMPLES");
    assert_eq!(seen("STRIP_AREA"), spec.strip_area, "STRIP_AREA");
    assert_eq!(seen("STRIP_L6"), spec.strip_l6, "STRIP_L6");
    assert_eq!(seen("TILE_ROWS_CAPACITY"), spec.tile_rows_capacity, "TILE_ROWS_CAPACITY");
    assert_eq!(seen("LOD_BUCKET"), spec.lod_bucket, "LOD_BUCKET");
    assert_eq!(seen("GROUND_CELLS"), spec.ground_cells, "GROUND_CELLS");
    assert_eq!(seen("GROUND_LEVELS"), spec.ground_levels, "GROUND_LEVELS");
    assert_eq!(seen("GROUND_COVER"), spec.ground_cover, "GROUND_COVER");
    assert_eq!(seen("CLUMP_SIZE_MM"), spec.clump_size_mm, "CLUMP_SIZE_MM");
    assert_eq!(seen("FLOWER_SHARE"), spec.flower_share, "FLOWER_SHARE");
    // The shaders see the constants build.rs generated for Rust.
    let shared = &words[FRAME_WORDS + specialization::COUNT..];
    let flags = gpu::FLAG_DEBUG_FORCE | gpu::FLAG_EVAL_BLADE | gpu::FLAG_CLUSTER_PUSH;
    let generated = [gpu::MAX_SEGMENTS, gpu::MAX_COLLIDERS, gpu::POSE_WORDS, flags, gpu::BINDING_POSES, gpu::SET_POSES];
    assert_eq!(shared, &generated, "MAX_SEGMENTS, MAX_COLLIDERS, POSE_WORDS, FLAG_*, BINDING_POSES, SET_POSES");
}

#[test]
fn validation_counts_an_invalid_call() {
    // The harness must be able to fail: a zero-sized buffer violates VUID-VkBufferCreateInfo-size-00912.
    let (result, messages) = with_device(&options(), false, |device| {
        let info = vk::BufferCreateInfo::default().size(0).usage(vk::BufferUsageFlags::STORAGE_BUFFER);
        // SAFETY: deliberately invalid create info; the handle (if any) is destroyed at once.
        unsafe {
            if let Ok(buffer) = device.raw.create_buffer(&info, None) {
                device.raw.destroy_buffer(buffer, None);
            }
        }
        Ok(())
    });
    result.expect("device created");
    assert!(messages.unwrap_or(0) >= 1, "the invalid call went unreported");
}
