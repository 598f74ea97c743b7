//! The wind's part of each frame in flight, read through set 0 (`shaders/animation/frame_forces.glsl`).

use crate::error::Result;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{Buffer, BufferDesc, Destroy, Device, Guard};
use ash::vk;

/// The wind's part of one frame in flight (`frame::PerFrame`), read through set 0: the wind
/// field at the cluster corners, written by the analytic field's pass on the GPU with the cull and
/// by the CPU before each submission with `--brute-force` (the thesis' path, 3.2.2), and the point
/// sources and colliders at the frame's time, written by the CPU (`render::wind::WindField`).
pub struct FrameForces {
    /// Host-visible wind at the cluster corners: velocity (x, y, z) in m/s and exposure.
    pub corners: Buffer,
    /// Host-visible point sources and colliders at the frame's time, relative to O.
    pub emitters: Buffer,
}

impl FrameForces {
    /// Set 0's resources of this frame, by the names `shaders/animation/frame_forces.glsl`
    /// declares them with (build.rs numbers them).
    pub fn scene_resources(&self) -> [(&'static str, Descriptor); 2] {
        [
            ("Corners", Descriptor::Buffer(self.corners.descriptor())),
            ("Emitters", Descriptor::Buffer(self.emitters.descriptor())),
        ]
    }

    /// The forces of frame `slot`: room for `corners` corner forces and `emitters` emitters.
    pub fn new(device: &Device, slot: usize, corners: u32, emitters: u32) -> Result<Self> {
        let vec4 = 16u64;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let buffer = |name: &str, count: u32, usage| {
            let name = format!("frame {slot} {name}");
            Buffer::new(device, &BufferDesc::upload(&name, vec4 * u64::from(count.max(1)), storage | usage))
        };
        // The corners are read back by tests (`Renderer::read_wind_corners`).
        let corners = Guard::new(device, buffer("wind corners", corners, vk::BufferUsageFlags::TRANSFER_SRC)?);
        let emitters = buffer("emitters", emitters, vk::BufferUsageFlags::empty())?;
        Ok(Self { corners: corners.take(), emitters })
    }
}

impl Destroy for FrameForces {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe { (self.corners, self.emitters).destroy(device) };
    }
}
