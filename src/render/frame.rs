//! Per-frame data: the uniform block every pass reads, and the resources one frame in flight
//! owns.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};

use crate::error::Result;
use crate::render::submission::SecondaryRecorders;
use crate::vk::commands::CommandRecorder;
use crate::vk::query::{StatisticsQueries, TimestampQueries};
use crate::vk::{sync, Access, Buffer, BufferDesc, Device};

/// Per-frame constants, std140 (`shaders/common.glsl`, struct `FrameUniforms`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// World → clip.
    pub view_proj: Mat4,
    /// xyz eye position, w simulation time in seconds.
    pub camera_position: Vec4,
    /// xyz unit vector towards the sun.
    pub sun_direction: Vec4,
    /// rgb linear sky colour, w fog density per metre.
    pub sky_color: Vec4,
    /// x terrain grid origin, y cell size.
    pub terrain: Vec4,
    /// x segments, y blade count, z terrain cells per side, w unused. (The blade geometry and
    /// the sRGB encoding are specialization constants, `render::specialization`.)
    pub params: UVec4,
    /// x magnitudes, y angles, z point sources, w corners per side.
    pub keyframes: UVec4,
    /// x records per pose, y colliders.
    pub keyframe_shape: UVec4,
}

const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 176);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, camera_position) == 64);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, params) == 128);

/// Light and atmosphere of the scene.
pub mod look {
    use super::*;

    /// Unit vector towards the sun: low, ahead-left of the default camera, so much of the field is
    /// back-lit and shows the translucency term.
    pub fn sun_direction() -> Vec3 {
        Vec3::new(-0.45, 0.5, -0.75).normalize()
    }

    /// Linear sky colour.
    pub const SKY: Vec3 = Vec3::new(0.42, 0.60, 0.86);
    /// Fog density per metre.
    pub const FOG_DENSITY: f32 = 0.012;

    /// sRGB transfer of one linear channel (the clear colour must match the shaders' encoding).
    pub fn encode_srgb(linear: f32) -> f32 {
        let c = linear.clamp(0.0, 1.0);
        if c <= 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    }
}

/// Timestamps per frame (two per pass and one at the end).
const TIMESTAMPS: u32 = 16;
/// Pipeline-statistics queries per frame (one per graphics pass).
const STATISTICS: u32 = 8;
/// Bytes of a frame's query results: 64-bit timestamps, then six 64-bit counters per query.
const QUERY_RESULT_BYTES: u64 = 8 * TIMESTAMPS as u64 + 48 * STATISTICS as u64;

/// Everything one frame in flight owns. The fence guards all of it: the CPU waits on it before
/// reusing the command buffer, rewriting the uniforms or reading the queries.
pub struct Frame {
    /// Command pool and buffer, reset each use.
    pub recorder: CommandRecorder,
    /// Signalled when this frame's submission completes (created signalled).
    pub fence: vk::Fence,
    /// Host-visible `FrameUniforms`.
    pub uniforms: Buffer,
    /// Host-visible forces at cluster corners, written before each submission (thesis 3.2.2).
    pub corners: Buffer,
    /// Host-visible point sources and colliders at this frame's time.
    pub emitters: Buffer,
    /// Set 0 of the scene passes, pointing at this frame's uniforms.
    pub descriptor_set: vk::DescriptorSet,
    /// Timestamps of this frame's passes.
    pub timestamps: TimestampQueries,
    /// Pipeline statistics of this frame's passes, when asked for and supported.
    pub statistics: Option<StatisticsQueries>,
    /// Host-visible copy of the timestamps (from 0) and statistics (from `statistics_offset`),
    /// written by the frame's last commands.
    pub query_results: Buffer,
    /// Offset of the statistics in `query_results`.
    pub statistics_offset: u64,
    /// The passes recorded, in order (timestamps i and i + 1 bracket pass i), with the
    /// pipeline-statistics query each one used, if any.
    pub passes: Vec<(&'static str, Option<u32>)>,
    /// Signalled when this frame's swapchain image is acquired (unused headless).
    pub acquire: vk::Semaphore,
    /// When recording of the submission in flight started, ended, and when its submission
    /// returned, until its fence is read.
    pub pending: Option<[std::time::Instant; 3]>,
    /// Worker command buffers of the `Secondary` submission strategy.
    pub secondaries: Option<SecondaryRecorders>,
    /// `Prerecorded` strategy: the colour view and size the command buffer was recorded for, with the
    /// previous colour and depth accesses its first barriers assume; while they hold, it is
    /// submitted again as is.
    pub recorded_for: Option<(vk::ImageView, vk::Extent2D, Access, Access)>,
}

impl Frame {
    /// Create the resources of frame `index`, with room for `corners` corner forces and
    /// `emitters` emitters.
    pub fn new(
        device: &Device,
        index: usize,
        descriptor_set: vk::DescriptorSet,
        corners: u32,
        emitters: u32,
        statistics: bool,
    ) -> Result<Self> {
        let mut buffers: Vec<Buffer> = Vec::new();
        let mut fence = vk::Fence::null();
        let mut recorder = None;
        let built = (|| {
            recorder = Some(CommandRecorder::new(device, &format!("frame {index} commands"))?);
            fence = sync::fence(device, true, &format!("frame {index} fence"))?;
            let vec4 = 16u64;
            for (name, size, usage) in [
                ("uniforms", std::mem::size_of::<FrameUniforms>() as u64, vk::BufferUsageFlags::UNIFORM_BUFFER),
                ("corner forces", vec4 * u64::from(corners), vk::BufferUsageFlags::STORAGE_BUFFER),
                ("emitters", vec4 * u64::from(emitters.max(1)), vk::BufferUsageFlags::STORAGE_BUFFER),
            ] {
                buffers.push(Buffer::new(device, &BufferDesc::upload(&format!("frame {index} {name}"), size, usage))?);
            }
            let name = format!("frame {index} query results");
            let results = BufferDesc::readback(&name, QUERY_RESULT_BYTES, vk::BufferUsageFlags::TRANSFER_DST);
            buffers.push(Buffer::new(device, &results)?);
            let timestamps = TimestampQueries::new(device, &format!("frame {index} timestamps"), TIMESTAMPS)?;
            let statistics = match statistics {
                true => StatisticsQueries::new(device, &format!("frame {index} statistics"), STATISTICS),
                false => Ok(None),
            };
            let statistics = match statistics {
                Ok(statistics) => statistics,
                Err(e) => {
                    // SAFETY: never used.
                    unsafe { timestamps.destroy(device) };
                    return Err(e);
                }
            };
            match sync::semaphore(device, &format!("frame {index} acquire")) {
                Ok(acquire) => Ok((timestamps, statistics, acquire)),
                Err(e) => {
                    // SAFETY: never used.
                    unsafe {
                        timestamps.destroy(device);
                        if let Some(statistics) = statistics {
                            statistics.destroy(device);
                        }
                    }
                    Err(e)
                }
            }
        })();
        match built {
            Ok((timestamps, statistics, acquire)) => {
                let mut buffers = buffers.into_iter();
                let mut next = || buffers.next().expect("four buffers");
                Ok(Self {
                    recorder: recorder.expect("created"),
                    fence,
                    uniforms: next(),
                    corners: next(),
                    emitters: next(),
                    query_results: next(),
                    statistics_offset: 8 * u64::from(TIMESTAMPS),
                    descriptor_set,
                    timestamps,
                    statistics,
                    passes: Vec::new(),
                    acquire,
                    pending: None,
                    secondaries: None,
                    recorded_for: None,
                })
            }
            Err(e) => {
                // SAFETY: nothing was submitted; destroying a null fence is a no-op.
                unsafe {
                    for buffer in buffers {
                        buffer.destroy(device);
                    }
                    device.raw.destroy_fence(fence, None);
                    if let Some(recorder) = recorder {
                        recorder.destroy(device);
                    }
                }
                Err(e)
            }
        }
    }

    /// Destroy everything (the descriptor set goes with its pool).
    ///
    /// # Safety
    /// The frame's fence must have signalled.
    pub unsafe fn destroy(self, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            self.timestamps.destroy(device);
            if let Some(statistics) = self.statistics {
                statistics.destroy(device);
            }
            self.uniforms.destroy(device);
            self.corners.destroy(device);
            self.emitters.destroy(device);
            self.query_results.destroy(device);
            device.raw.destroy_fence(self.fence, None);
            device.raw.destroy_semaphore(self.acquire, None);
            self.recorder.destroy(device);
            if let Some(mut secondaries) = self.secondaries {
                secondaries.destroy(device);
            }
        }
    }
}
