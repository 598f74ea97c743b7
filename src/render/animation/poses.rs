//! Pose records: the blade pass's input from a blade response that poses blades once per blade
//! (`BladeInput::PoseRecords`), and with the cull the drawn blades' placed levels that
//! `passes::BladeLevelsPass` makes of them. They belong to the renderer, not to a response: a
//! response's passes write the records (set `SET_POSES`, `shaders/common/bindings.glsl`, with
//! `POSE_WRITER`), whichever response it is, and the blade pass reads them.

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::vk::descriptor::{Resource as Descriptor, SetLayout};
use crate::vk::{Buffer, BufferDesc, Destroy, Device, Guard, TexelView};
use ash::vk;

/// A record's point over the blade's height lies within ±POSE_SCALE (`shaders/common/bindings.glsl`).
pub const POSE_SCALE: f32 = 2.0;

/// Level `level` of record `record` of `records` (read back, `Renderer::read_pose_records`) with
/// `model_segments` segments: its point in the blade's frame (x across, y up, z along the
/// normal), in metres for a blade `height` tall.
pub fn recorded_point(records: &[u32], (record, level): (usize, u32), model_segments: u32, height: f32) -> glam::Vec3 {
    let at = (record * (model_segments as usize + 1) + level as usize) * gpu::POSE_WORDS as usize;
    let snorm = |bits: u32| (f32::from(bits as u16 as i16) / 32767.0).max(-1.0);
    let (w0, w1) = (records[at], records[at + 1]);
    glam::Vec3::new(snorm(w0), snorm(w0 >> 16), snorm(w1)) * (POSE_SCALE * height)
}

/// Pose records and placed levels, and set `SET_POSES` pointing at them.
pub struct PoseRecords {
    /// Pose records (`POSE_WORDS` words per level).
    pub poses: Buffer,
    /// Placed, lit levels (`passes::BladeLevelsPass`), as many records as `level_records`.
    pub levels: Buffer,
    /// The placed levels as RG32UI texels, as blade.vert fetches them.
    pub level_texels: TexelView,
    /// Records `levels` holds.
    pub level_records: u32,
    /// Whether there is room for records (a response writes them), not a stand-in.
    pub written: bool,
    pool: vk::DescriptorPool,
    /// Set `SET_POSES`.
    pub set: vk::DescriptorSet,
}

impl PoseRecords {
    /// Room for `records` pose records and `levels` placed levels of `segments` segments, as
    /// many as one storage buffer holds (a stand-in of one level for a count of 0: the blade
    /// shaders declare the set whichever path runs), and the set of `set_layout` over them.
    pub fn new(device: &Device, set_layout: &SetLayout, (records, levels): (u32, u32), segments: u32) -> Result<Self> {
        use crate::render::scene_gpu::{level_bytes, level_records, pose_bytes};
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let pose_size = match records {
            0 => 4 * u64::from(gpu::POSE_WORDS),
            _ => pose_bytes(records, segments),
        };
        let level_records = level_records(device, levels, segments);
        let level_size = match level_records {
            0 => 8 * u64::from(gpu::LEVEL_UVEC2S),
            _ => level_bytes(level_records, segments),
        };
        // A transfer source too: `Renderer::read_pose_records` copies them out for tests.
        let pose_usage = usage | vk::BufferUsageFlags::TRANSFER_SRC;
        let poses =
            Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("blade poses", pose_size, pose_usage))?);
        let level_usage = usage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let levels = BufferDesc::gpu_only("blade levels", level_size, level_usage);
        let levels = Guard::new(device, Buffer::new(device, &levels)?);
        let level_texels = TexelView::new(device, &levels, vk::Format::R32G32_UINT, "blade level texels")?;
        let level_texels = Guard::new(device, level_texels);
        let (pool, sets) = set_layout.allocate(device, "pose set", 1)?;
        let made = Guard::new(
            device,
            Self {
                poses: poses.take(),
                levels: levels.take(),
                level_texels: level_texels.take(),
                level_records,
                written: records > 0,
                pool,
                set: sets[0],
            },
        );
        set_layout.write(
            device,
            made.set,
            "pose set",
            &[
                (gpu::BINDING_POSES, Descriptor::Buffer(made.poses.descriptor())),
                (gpu::BINDING_LEVELS, Descriptor::Buffer(made.levels.descriptor())),
                (gpu::BINDING_LEVEL_TEXELS, Descriptor::Texels(made.level_texels.raw)),
            ],
        )?;
        Ok(made.take())
    }

    /// The buffers the graph tracks (forgotten when the records are replaced).
    pub fn buffers(&self) -> [vk::Buffer; 2] {
        [self.poses.raw, self.levels.raw]
    }
}

impl Destroy for PoseRecords {
    unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pool);
            device.raw.destroy_descriptor_pool(self.pool, None);
            self.poses.destroy(device);
            self.level_texels.destroy(device);
            self.levels.destroy(device);
        }
    }
}
