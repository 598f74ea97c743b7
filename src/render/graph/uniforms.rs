//! A pass's own uniform block (`PassUniforms`): a small host-visible buffer per frame in flight
//! that the graph fills, on each frame the pass runs, with what `Pass::uniforms` returns, before
//! the frame is submitted. The pass points a binding of its own set at `resource(slot)`; the
//! buffer is a storage buffer too, so under the lavapipe profile a value that decides control
//! flow can be read through a storage binding of the same block (`shaders/common/profile.glsl`'s
//! rule).

use std::cell::RefCell;

use ash::vk;

use crate::error::{Error, Result};
use crate::vk::descriptor::Resource;
use crate::vk::{Buffer, BufferDesc, Destroy, Device, Guard};

/// One uniform block of `size` bytes per frame in flight.
pub struct PassUniforms {
    name: String,
    size: u64,
    /// By frame slot; the host writes slot k's only after its fence (the graph plans a frame
    /// after `begin_frame` waited for it).
    buffers: RefCell<Vec<Buffer>>,
}

impl PassUniforms {
    /// `frames` blocks of `size` bytes (a std140 block's size), named after `name`. On failure
    /// nothing is left.
    pub fn new(device: &Device, name: &str, size: u64, frames: usize) -> Result<Self> {
        let usage = vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER;
        let mut buffers = Guard::new(device, Vec::with_capacity(frames));
        for slot in 0..frames {
            let label = format!("{name} uniforms #{slot}");
            let mut buffer = Buffer::new(device, &BufferDesc::upload(&label, size.max(16), usage))?;
            buffer.write(0, &vec![0u8; buffer.size as usize]);
            buffers.push(buffer);
        }
        Ok(Self { name: name.to_owned(), size, buffers: RefCell::new(buffers.take()) })
    }

    /// Frame slot `slot`'s block, for a descriptor write.
    pub fn resource(&self, slot: usize) -> Resource {
        Resource::Buffer(self.descriptor(slot))
    }

    /// Frame slot `slot`'s block as a buffer range.
    pub fn descriptor(&self, slot: usize) -> vk::DescriptorBufferInfo {
        self.buffers.borrow()[slot].descriptor()
    }

    /// Frame slot `slot`'s buffer (e.g. to declare a read of it).
    pub fn buffer(&self, slot: usize) -> vk::Buffer {
        self.buffers.borrow()[slot].raw
    }

    /// What the host last wrote into slot `slot`'s block.
    pub fn contents(&self, slot: usize) -> Vec<u8> {
        self.buffers.borrow()[slot].mapped()[..self.size as usize].to_vec()
    }

    /// Write `bytes` into slot `slot`'s block (the graph's, from `Pass::uniforms`).
    pub(super) fn write(&self, slot: usize, bytes: &[u8]) -> Result<()> {
        if bytes.len() as u64 != self.size {
            return Err(Error::Internal(format!(
                "{}: {} bytes of uniforms for a block of {}",
                self.name,
                bytes.len(),
                self.size
            )));
        }
        self.buffers.borrow_mut()[slot].write(0, bytes);
        Ok(())
    }

    /// Destroy the buffers.
    ///
    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        for buffer in self.buffers.into_inner() {
            // SAFETY: per the contract.
            unsafe { buffer.destroy(device) };
        }
    }
}

impl Destroy for PassUniforms {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { PassUniforms::destroy(self, device) };
    }
}
