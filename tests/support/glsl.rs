//! A test's own compute shader: GLSL under `tests/shaders/` compiled by glslangValidator at test
//! time (no edit to the library or its build script), with its own set layout, pipeline layout
//! (push constants in the compute stage) and descriptor sets. Included with
//! `#[path = "support/glsl.rs"] mod glsl;` by the tests that define a pass of their own.
#![allow(dead_code)] // each test crate uses a different subset of these helpers

use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use ash::vk;
use meadow::vk::descriptor::{self, Binding};
use meadow::vk::{pipeline, Device};

/// SPIR-V of `tests/shaders/NAME`, compiled now.
pub fn compile(name: &str) -> Vec<u8> {
    compile_with(name, &[])
}

/// SPIR-V of `tests/shaders/NAME` that includes the library's headers (`#include
/// "common/bindings.glsl"`, from `shaders/`), for `profile`'s backend (its define, as build.rs
/// gives it).
pub fn compile_for(name: &str, profile: meadow::vk::profile::Profile) -> Vec<u8> {
    let define = match profile {
        meadow::vk::profile::Profile::Lavapipe => "-DMEADOW_PROFILE_LAVAPIPE",
        meadow::vk::profile::Profile::Generic => "-DMEADOW_PROFILE_GENERIC",
    };
    let include = format!("-I{}", Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders").display());
    compile_with(name, &[define, &include])
}

/// SPIR-V of `tests/shaders/NAME` compiled with the extra glslang arguments `args`.
pub fn compile_with(name: &str, args: &[&str]) -> Vec<u8> {
    static RUN: AtomicUsize = AtomicUsize::new(0);
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shaders").join(name);
    let run = RUN.fetch_add(1, Ordering::Relaxed);
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.{}.{run}.spv", std::process::id()));
    let glslang = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    let output = Command::new(&glslang)
        .args(["-V", "--target-env", "vulkan1.2"])
        .args(args)
        .arg(&source)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap_or_else(|e| panic!("run {glslang} (Debian package glslang-tools): {e}"));
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stdout));
    let spirv = std::fs::read(&out).expect("read the SPIR-V");
    let _ = std::fs::remove_file(&out);
    spirv
}

/// A compute pipeline of a test shader, its one set layout of storage buffers, and `sets` sets.
pub struct ComputePipeline {
    pub set_layout: vk::DescriptorSetLayout,
    pub layout: vk::PipelineLayout,
    pub pipeline: vk::Pipeline,
    pub pool: vk::DescriptorPool,
    pub sets: Vec<vk::DescriptorSet>,
}

impl ComputePipeline {
    /// `tests/shaders/NAME` with `buffers` storage buffers at bindings 0.., `push` bytes of push
    /// constants, and `sets` descriptor sets.
    pub fn new(device: &Device, name: &str, buffers: u32, push: u32, sets: u32) -> meadow::Result<Self> {
        let spirv = compile(name);
        let bindings: Vec<Binding> = (0..buffers)
            .map(|binding| Binding {
                binding,
                kind: vk::DescriptorType::STORAGE_BUFFER,
                stages: vk::ShaderStageFlags::COMPUTE,
            })
            .collect();
        let set_layout = descriptor::set_layout(device, name, &bindings)?;
        let range = vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: push };
        let layout = pipeline::layout(device, name, &[set_layout], &[range])?;
        let pipeline = pipeline::compute(device, name, &spirv, layout, &[])?;
        let (pool, sets) = descriptor::allocate_sets(device, name, set_layout, &bindings, sets)?;
        Ok(Self { set_layout, layout, pipeline, pool, sets })
    }

    /// Point set `set`'s bindings 0.. at `buffers` (whole buffers).
    pub fn write(&self, device: &Device, set: usize, buffers: &[vk::Buffer]) {
        let writes: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(binding, &buffer)| {
                let info = vk::DescriptorBufferInfo { buffer, offset: 0, range: vk::WHOLE_SIZE };
                (binding as u32, vk::DescriptorType::STORAGE_BUFFER, descriptor::Resource::Buffer(info))
            })
            .collect();
        descriptor::write(device, self.sets[set], &writes);
    }

    /// Bind the pipeline and set `set`, push `push`, dispatch `groups` workgroups.
    pub fn dispatch(&self, device: &Device, cmd: vk::CommandBuffer, set: usize, push: &[u8], groups: u32) {
        let bind = vk::PipelineBindPoint::COMPUTE;
        // SAFETY: cmd is recording outside a rendering instance; the set matches the layout and
        // points at live buffers; the push fits the layout's range.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, bind, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, bind, self.layout, 0, &[self.sets[set]], &[]);
            device.raw.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::COMPUTE, 0, push);
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
    }

    /// Destroy everything (the sets go with the pool).
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            meadow::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            meadow::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            meadow::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            meadow::vk::live::destroyed(self.set_layout);
            device.raw.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
