//! Belyaev's virtual blades (§3.3), the first pass of the virtually-inertial response
//! (`virtual_inertial`): `shaders/animation/virtual_blades.comp` steps an upright segment chain
//! (`chain`) at every wind corner under the corner's wind and writes its virtual moments, as
//! forces, into the virtual wind the drawn blades read. The pass reads this frame's corners and the
//! side of its state pair the last submitted frame wrote, and writes the other side and the
//! virtual wind; the graph orders it after the wind field's pass and before the drawn blades'.

use std::cell::Cell;
use std::rc::Rc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{PassSet, PassSetDesc};
use crate::render::shaders;
use crate::vk::descriptor::Resource;
use crate::vk::{pipeline, Access, Device, Guard};

/// Floats of a virtual blade's state: ψ, then ω, per joint (virtual_blades.comp's
/// `VIRTUAL_STATE_FLOATS`).
pub const STATE_FLOATS: u32 = 6 * crate::render::animation::chain::CHAIN_SEGMENTS as u32;

/// `VirtualValues` / `VirtualControl` of virtual_blades.comp (std140, one block bound twice).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VirtualFrame {
    /// Corners of every level (the pass sets those of the levels it steps), corners per side of a
    /// level, 1 to restart every virtual blade, steps to take.
    pub counts: UVec4,
    /// O's move since the last frame (x, z, m), the step (s), 0.
    pub motion: Vec4,
    /// k/J (1/s²), d/J (1/s), the virtual blade's height (m), 0.
    pub chain: Vec4,
    /// Per level: its first corner relative to O (x, z), its spacing, 0.
    pub levels: [Vec4; gpu::WIND_LEVELS as usize],
}

/// What the pass runs over: the buffers its response owns.
pub struct VirtualBuffers {
    /// Each frame slot's wind at the corners (`ResponseSetup::wind`).
    pub corners: Vec<vk::Buffer>,
    /// The state pair, `STATE_FLOATS` floats a corner each.
    pub state: [vk::DescriptorBufferInfo; 2],
    /// The virtual wind, a vec4 per corner and joint.
    pub virtual_wind: vk::DescriptorBufferInfo,
}

/// The virtual blades' pipeline, a set per frame slot and side of the state pair, its uniform
/// block.
pub struct VirtualBladesPass {
    pipeline: vk::Pipeline,
    /// Set `side · frames + slot` writes side `side` and reads the other.
    set: PassSet,
    uniforms: PassUniforms,
    frames: usize,
    corners: Vec<vk::Buffer>,
    state: [vk::Buffer; 2],
    virtual_wind: vk::Buffer,
    /// This frame's block, which the response sets before each frame.
    frame: Rc<Cell<VirtualFrame>>,
    /// A frame was dropped: the pair may not hold the last frame's state, so the next restarts.
    dropped: Cell<bool>,
    /// The levels the last planned frame stepped: a frame that steps more restarts them all.
    stepped: Cell<u32>,
}

impl VirtualBladesPass {
    /// Build the pipeline and the sets over `buffers` for `frames` frames in flight.
    pub fn new(
        device: &Device,
        frames: usize,
        buffers: &VirtualBuffers,
        frame: Rc<Cell<VirtualFrame>>,
    ) -> Result<Self> {
        let size = std::mem::size_of::<VirtualFrame>() as u64;
        let uniforms = Guard::new(device, PassUniforms::new(device, "virtual blades", size, frames)?);
        let code = shaders::VIRTUAL_BLADES_COMP.code(device.profile);
        let shaders = [("virtual_blades.comp", code)];
        let desc =
            PassSetDesc { name: "virtual blades", shaders: &shaders, before: &[], push: &[], frames: 2 * frames };
        let set = PassSet::new(device, &desc, |index| {
            let (side, slot) = (index / frames, index % frames);
            vec![
                ("VirtualValues", uniforms.resource(slot)),
                ("VirtualControl", uniforms.resource(slot)),
                (
                    "Corners",
                    Resource::Buffer(
                        vk::DescriptorBufferInfo::default().buffer(buffers.corners[slot]).range(vk::WHOLE_SIZE),
                    ),
                ),
                ("VirtualPrevious", Resource::Buffer(buffers.state[1 - side])),
                ("VirtualCurrent", Resource::Buffer(buffers.state[side])),
                ("VirtualWind", Resource::Buffer(buffers.virtual_wind)),
            ]
        })?;
        let set = Guard::new(device, set);
        let pipeline = pipeline::compute(device, "virtual blades", code, set.layout, &[])?;
        Ok(Self {
            pipeline,
            set: set.take(),
            uniforms: uniforms.take(),
            frames,
            corners: buffers.corners.clone(),
            state: [buffers.state[0].buffer, buffers.state[1].buffer],
            virtual_wind: buffers.virtual_wind.buffer,
            frame,
            dropped: Cell::new(false),
            stepped: Cell::new(0),
        })
    }

    /// The wind levels this frame steps: of a block field's levels, those that blades within the
    /// blade range of the camera (`FrameUniforms::lod.x`; the camera is within a block of O's)
    /// read (`field_gpu::levels_reaching`); a stored field's one.
    fn levels_read(&self, ctx: &PassContext) -> u32 {
        let frame = self.frame.get();
        let levels = frame.counts.x / (frame.counts.y * frame.counts.y);
        if levels <= 1 {
            return levels;
        }
        let reach = ctx.uniforms.lod.x + crate::scene::field::BLOCK_SIZE;
        crate::render::field_gpu::levels_reaching(frame.levels[0].z, reach).min(levels)
    }

    /// The corners of the levels this frame steps (levels are stored innermost first).
    fn corners_stepped(&self, ctx: &PassContext) -> u32 {
        let per_side = self.frame.get().counts.y;
        self.levels_read(ctx) * per_side * per_side
    }

    /// The side of the state pair frame `index` writes.
    fn side(index: u64) -> usize {
        (index % 2) as usize
    }
}

impl Pass for VirtualBladesPass {
    fn name(&self) -> &'static str {
        "virtual blades"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let side = Self::side(ctx.clock.index);
        Some(
            Declaration::compute()
                .buffer(self.corners[ctx.slot], Access::ComputeShaderRead)
                .buffer(self.state[1 - side], Access::ComputeShaderRead)
                .buffer(self.state[side], Access::ComputeShaderWrite)
                .buffer(self.virtual_wind, Access::ComputeShaderWrite),
        )
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        let set = Self::side(ctx.clock.index) * self.frames + ctx.slot;
        // SAFETY: cmd is recording; the pipeline and the set are live and match.
        unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline) };
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, set);
        let groups = self.corners_stepped(ctx).div_ceil(gpu::WIND_GROUP);
        // SAFETY: as above.
        unsafe { device.raw.cmd_dispatch(cmd, groups, 1, 1) };
        Ok(())
    }

    fn uniforms(&self, ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        let mut frame = self.frame.get();
        let levels = self.levels_read(ctx);
        // Levels that were not stepped hold stale state.
        if self.dropped.take() || levels > self.stepped.replace(levels) {
            frame.counts.z = 1;
        }
        frame.counts.x = self.corners_stepped(ctx);
        Some((&self.uniforms, bytemuck::bytes_of(&frame).to_vec()))
    }

    fn frame_dropped(&self) {
        self.dropped.set(true);
        self.stepped.set(0);
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
        }
    }
}
