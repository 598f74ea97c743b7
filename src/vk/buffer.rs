//! Buffers: a `BufferDesc` value describes one, `Buffer` owns the handle and its gpu-allocator
//! allocation. Leaves are freed explicitly with `destroy` by their owner.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkContext};
use crate::vk::device::Device;
use crate::vk::guard::Guard;

/// Description of a buffer: size, usage, memory location, debug name.
#[derive(Clone, Copy, Debug)]
pub struct BufferDesc<'a> {
    /// Size in bytes.
    pub size: vk::DeviceSize,
    /// Usage flags.
    pub usage: vk::BufferUsageFlags,
    /// Where the memory lives.
    pub location: MemoryLocation,
    /// Name of the buffer and of its allocation.
    pub name: &'a str,
}

impl<'a> BufferDesc<'a> {
    /// Device-local memory, filled by transfers or shaders.
    pub fn gpu_only(name: &'a str, size: vk::DeviceSize, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage, location: MemoryLocation::GpuOnly, name }
    }

    /// Host-visible memory written by the CPU every frame (uniforms, staging).
    pub fn upload(name: &'a str, size: vk::DeviceSize, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage, location: MemoryLocation::CpuToGpu, name }
    }

    /// Host-visible, cached memory the CPU reads back.
    pub fn readback(name: &'a str, size: vk::DeviceSize, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage, location: MemoryLocation::GpuToCpu, name }
    }
}

/// A buffer and its memory.
pub struct Buffer {
    /// The handle.
    pub raw: vk::Buffer,
    /// Size in bytes.
    pub size: vk::DeviceSize,
    allocation: Allocation,
}

impl Buffer {
    /// Create the buffer, allocate and bind its memory, name both.
    pub fn new(device: &Device, desc: &BufferDesc) -> Result<Self> {
        let info = vk::BufferCreateInfo::default()
            .size(desc.size.max(1))
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info.
        let raw = super::live::created(unsafe { device.raw.create_buffer(&info, None) }.vk("vkCreateBuffer")?);
        let raw = Guard::new(device, raw);
        // SAFETY: raw was just created from this device.
        let requirements = unsafe { device.raw.get_buffer_memory_requirements(*raw) };
        let allocation = device.allocate(&AllocationCreateDesc {
            name: desc.name,
            requirements,
            location: desc.location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = Guard::new(device, allocation.map_err(|source| Error::allocation(desc.name, source))?);
        // SAFETY: the allocation satisfies the buffer's requirements.
        unsafe { device.raw.bind_buffer_memory(*raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindBufferMemory")?;
        let (raw, allocation) = (raw.take(), allocation.take());
        device.set_name(raw, desc.name);
        Ok(Self { raw, size: desc.size, allocation })
    }

    /// Create a host-visible buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(device: &Device, desc: &BufferDesc, data: &[T]) -> Result<Self> {
        let mut buffer = Self::new(device, desc)?;
        buffer.write(0, data);
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer.
    ///
    /// # Panics
    /// If the buffer is not host-visible: a programming error, not an input error.
    pub fn mapped(&self) -> &[u8] {
        let bytes = self.allocation.mapped_slice().expect("buffer is host-visible");
        &bytes[..self.size as usize]
    }

    /// Copy `data` into a host-visible buffer at byte `offset`. Host writes become visible to the
    /// device at the next queue submission (host-coherent memory from gpu-allocator).
    ///
    /// # Panics
    /// If the buffer is not host-visible or the data does not fit: programming errors.
    pub fn write<T: bytemuck::Pod>(&mut self, offset: usize, data: &[T]) {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mapped = self.allocation.mapped_slice_mut().expect("buffer is host-visible");
        mapped[offset..offset + bytes.len()].copy_from_slice(bytes);
    }

    /// Descriptor info covering the whole buffer.
    pub fn descriptor(&self) -> vk::DescriptorBufferInfo {
        vk::DescriptorBufferInfo { buffer: self.raw, offset: 0, range: vk::WHOLE_SIZE }
    }

    /// Free the memory and destroy the handle.
    ///
    /// # Safety
    /// No pending GPU work may use the buffer.
    pub unsafe fn destroy(self, device: &Device) {
        device.free(self.allocation, "a buffer");
        // SAFETY: caller guarantees the GPU is done with it.
        unsafe {
            super::live::destroyed(self.raw);
            device.raw.destroy_buffer(self.raw, None)
        };
    }
}

/// A typed view of a buffer, bound as a uniform texel buffer (`samplerBuffer` / `usamplerBuffer`
/// in GLSL). On llvmpipe a `texelFetch` gathers the lanes' texels in vector code, where a
/// storage-buffer load walks the SIMD lanes one by one with a bounds test and a branch each
/// (Mesa 22.3's `emit_load_mem`): measured in the cull, nine storage loads per blade cost about
/// 4 ms a frame at the unbounded field.
pub struct TexelView {
    /// The handle.
    pub raw: vk::BufferView,
}

impl TexelView {
    /// A view of all of `buffer` (created with `UNIFORM_TEXEL_BUFFER` usage) as `format` texels.
    pub fn new(device: &Device, buffer: &Buffer, format: vk::Format, name: &str) -> Result<Self> {
        let info =
            vk::BufferViewCreateInfo::default().buffer(buffer.raw).format(format).offset(0).range(vk::WHOLE_SIZE);
        // SAFETY: valid create info over a live buffer of this device.
        let raw = super::live::created(unsafe { device.raw.create_buffer_view(&info, None) }.vk("vkCreateBufferView")?);
        device.set_name(raw, name);
        Ok(Self { raw })
    }

    /// Destroy the view.
    ///
    /// # Safety
    /// No pending GPU work may use the view.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: caller guarantees the GPU is done with it.
        unsafe {
            super::live::destroyed(self.raw);
            device.raw.destroy_buffer_view(self.raw, None)
        };
    }
}
