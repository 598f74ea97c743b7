//! The far field's placement (`shaders/far_field/far_place.comp`): each frame, one invocation per
//! lattice point of every ring writes the plants that stand there and are seen, and counts them
//! into the far pass's indirect draw. Two steps: the draw's instance count reset (a transfer),
//! then the dispatch, which the graph orders after it.
//!
//! Reads: the ground (heights and cover, `common/ground.glsl`), its parameters. Writes: the plants
//! and the draw ([`FarPlacePass::plants`], [`FarPlacePass::draw`], read by `FarPass`).

use ash::vk;

use super::{FarParams, CAPACITY, PLACE_GROUP};
use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{self, PassSet, SceneSets};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{pipeline, Access, Buffer, BufferDesc, Device, Guard};

/// Bytes of a placed plant (`FarPlant` of `far_field.glsl`).
const PLANT_BYTES: u64 = 32;

/// The placement's pipeline, its set and uniforms, and the plants and draw it writes.
pub struct FarPlacePass {
    pipeline: vk::Pipeline,
    set: PassSet,
    uniforms: PassUniforms,
    params: FarParams,
    plants: Buffer,
    draw: Buffer,
    /// Lattice points visited.
    points: u32,
    /// The first word of the draw: indices of one plant.
    index_count: u32,
    /// The ground it reads.
    ground: [vk::Buffer; 2],
}

impl FarPlacePass {
    /// Build the pass for `params` (`points`: lattice points of its rings; `index_count`: the
    /// mesh's indices a plant).
    pub fn new(
        device: &Device,
        (sets, constants): (SceneSets, &Specialization),
        scene: &SceneGpu,
        params: FarParams,
        (points, index_count): (u32, u32),
    ) -> Result<Self> {
        let name = "far placement";
        let spirv = shaders::FAR_PLACE_COMP.code(device.profile);
        let size = std::mem::size_of::<FarParams>() as u64;
        let uniforms = Guard::new(device, PassUniforms::new(device, name, size, sets.frames)?);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let plants = Guard::new(
            device,
            Buffer::new(device, &BufferDesc::gpu_only("far plants", PLANT_BYTES * u64::from(CAPACITY), storage))?,
        );
        let usage = storage
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let draw = Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("far draw", 20, usage))?);
        let set = PassSet::new(device, &sets.desc(name, &[(name, spirv)]), |slot| {
            vec![
                ("FarParamsBlock", uniforms.resource(slot)),
                ("FarPlants", Descriptor::Buffer(plants.descriptor())),
                ("FarDraw", Descriptor::Buffer(draw.descriptor())),
            ]
        })?;
        let set = Guard::new(device, set);
        let pipeline = pipeline::compute(device, name, spirv, set.layout, &constants.named())?;
        Ok(Self {
            pipeline,
            set: set.take(),
            uniforms: uniforms.take(),
            params,
            plants: plants.take(),
            draw: draw.take(),
            points,
            index_count,
            ground: [scene.ground.texels.raw, scene.ground.cover.0.raw],
        })
    }

    /// The plants it writes.
    pub fn plants(&self) -> vk::DescriptorBufferInfo {
        self.plants.descriptor()
    }

    /// The indirect draw it writes (`VkDrawIndexedIndirectCommand`).
    pub fn draw(&self) -> vk::Buffer {
        self.draw.raw
    }
}

impl Pass for FarPlacePass {
    fn name(&self) -> &'static str {
        "far placement"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fetch = ctx.device.profile.compute_fetch();
        let declaration = Declaration::compute()
            .step("reset")
            .buffer(self.draw.raw, Access::TransferWrite)
            .step("place")
            .buffer(self.draw.raw, Access::ComputeShaderRead)
            .buffer(self.draw.raw, Access::ComputeShaderWrite)
            .buffer(self.plants.raw, Access::ComputeShaderWrite)
            .buffer(self.ground[0], fetch)
            .buffer(self.ground[1], fetch);
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        if ctx.step == 0 {
            let command = [self.index_count, 0, 0, 0, 0];
            // SAFETY: cmd is recording outside a rendering instance; the buffer holds 20 bytes.
            unsafe { device.raw.cmd_update_buffer(cmd, self.draw.raw, 0, bytemuck::cast_slice(&command)) };
            return Ok(());
        }
        recording::bind_scene_set(device, ctx, cmd, self.set.layout, vk::PipelineBindPoint::COMPUTE);
        self.set.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        // SAFETY: as above; both sets and the pipeline are bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, self.points.div_ceil(PLACE_GROUP), 1, 1);
        }
        Ok(())
    }

    fn uniforms(&self, _ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        Some((&self.uniforms, bytemuck::bytes_of(&self.params).to_vec()))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
            self.plants.destroy(device);
            self.draw.destroy(device);
        }
    }
}
