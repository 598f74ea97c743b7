//! GPU tests of the shared data layout and of the validation harness itself.

use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::shaders;
use meadow::scene::{BladeInstance, Scene};
use meadow::vk::descriptor::{self, Binding, Resource};
use meadow::vk::{commands, pipeline, sync, Access, Buffer, BufferDesc, Device, DeviceSelector};

fn options() -> GpuOptions {
    GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") }
}

/// Write `blades` from Rust, read every field back through `blade_readback.comp`.
fn read_back(device: &Arc<Device>, blades: &[BladeInstance]) -> meadow::Result<Vec<u32>> {
    let input = Buffer::with_data(
        device,
        &BufferDesc::upload("test blades", std::mem::size_of_val(blades) as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
        blades,
    )?;
    let output = Buffer::new(
        device,
        &BufferDesc::readback("test fields", 32 * blades.len() as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
    )?;
    let bindings = [
        Binding { binding: 0, kind: vk::DescriptorType::STORAGE_BUFFER, stages: vk::ShaderStageFlags::COMPUTE },
        Binding { binding: 1, kind: vk::DescriptorType::STORAGE_BUFFER, stages: vk::ShaderStageFlags::COMPUTE },
    ];
    let set_layout = descriptor::set_layout(device, "readback set layout", &bindings)?;
    let layout = pipeline::layout(device, "readback layout", &[set_layout], &[])?;
    let pipe = pipeline::compute(device, "blade readback", shaders::BLADE_READBACK_COMP, layout, &[])?;
    let (pool, sets) = descriptor::allocate_sets(device, "readback", set_layout, &bindings, 1)?;
    descriptor::write(
        device,
        sets[0],
        &[
            (0, vk::DescriptorType::STORAGE_BUFFER, Resource::Buffer(input.descriptor())),
            (1, vk::DescriptorType::STORAGE_BUFFER, Resource::Buffer(output.descriptor())),
        ],
    );
    let groups = (blades.len() as u32).div_ceil(64);
    let submitted = commands::submit_and_wait(device, "readback", |cmd| {
        // SAFETY: all objects are live; host writes are visible at submission.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipe);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &sets, &[]);
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
        let to_host = sync::buffer_barrier(output.raw, &[Access::ComputeShaderWrite], &[Access::HostRead]);
        sync::cmd_barriers(device, cmd, &[to_host], &[]);
        Ok(())
    });
    let words = bytemuck::cast_slice::<u8, u32>(output.mapped()).to_vec();
    // SAFETY: submit_and_wait waited for the dispatch.
    unsafe {
        device.raw.destroy_descriptor_pool(pool, None);
        device.raw.destroy_pipeline(pipe, None);
        device.raw.destroy_pipeline_layout(layout, None);
        device.raw.destroy_descriptor_set_layout(set_layout, None);
        input.destroy(device);
        output.destroy(device);
    }
    submitted.map(|()| words)
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
