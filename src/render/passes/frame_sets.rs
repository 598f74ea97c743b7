//! What a pass that reads a frame's own image needs (the depth pyramid reads the frame's depth,
//! the resolve its multisampled colour): a set layout and pipeline layout, one descriptor set per
//! frame in flight (pointed at the frame's image when the pass is recorded: that set's previous
//! use ended with the slot's fence) and a nearest, clamped sampler. The set's layout is what the
//! pass's shaders bind in set 0 (reflected, `descriptor::SetLayout::reflected`).

use ash::vk;

use crate::error::Result;
use crate::vk::descriptor::SetLayout;
use crate::vk::{pipeline, Destroy, Device, Guard};

/// A set per frame in flight, their layouts and a sampler.
pub struct FrameSets {
    /// The sets' layout.
    pub set_layout: SetLayout,
    /// The pipeline layout of that one set.
    pub layout: vk::PipelineLayout,
    pool: vk::DescriptorPool,
    /// One set per frame in flight, by slot.
    pub sets: Vec<vk::DescriptorSet>,
    /// Nearest, clamped.
    pub sampler: vk::Sampler,
}

impl FrameSets {
    /// Build `frames` sets of set 0 of `shaders` (the pass's stages, `(name, SPIR-V)`), named
    /// after `name`. On failure nothing is left.
    pub fn new(device: &Device, name: &str, shaders: &[(&str, &[u8])], frames: usize) -> Result<Self> {
        // Null handles are ignored when a failure destroys what was made.
        let mut made = Guard::new(
            device,
            Self {
                set_layout: SetLayout::default(),
                layout: vk::PipelineLayout::null(),
                pool: vk::DescriptorPool::null(),
                sets: Vec::new(),
                sampler: vk::Sampler::null(),
            },
        );
        {
            made.set_layout = SetLayout::reflected(device, &format!("{name} set layout"), shaders, 0)?;
            made.layout = pipeline::layout(device, &format!("{name} layout"), &[made.set_layout.raw], &[])?;
            let sets = made.set_layout.allocate(device, &format!("{name} sets"), frames as u32)?;
            (made.pool, made.sets) = sets;
            made.sampler = crate::vk::image::clamped_sampler(device, vk::Filter::NEAREST, &format!("{name} sampler"))?;
        }
        Ok(made.take())
    }

    /// Destroy everything (the sets go with the pool).
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(&self, device: &Device) {
        // SAFETY: per the contract; destroying null handles is a no-op.
        unsafe {
            crate::vk::live::destroyed(self.sampler);
            device.raw.destroy_sampler(self.sampler, None);
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
            SetLayout::destroy(&self.set_layout, device);
        }
    }
}

impl Destroy for FrameSets {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { FrameSets::destroy(&self, device) };
    }
}
