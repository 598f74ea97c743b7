//! The far field's placement (`shaders/far_field/far_place.comp`): each frame, one invocation per
//! lattice point of every ring writes the plants that stand there and are seen, and counts them
//! into the far pass's indirect draw. Two steps: the draw's instance count reset (a transfer),
//! then the dispatch, which the graph orders after it. With `--fade blend`, ordered
//! (`far_field::order`): the dispatch writes every point's slot far to near, and a third step
//! (`far_order.comp`, one workgroup) compacts them in that order and counts them.
//!
//! Reads: the ground (heights and cover, `common/ground.glsl`), its parameters; ordered, the order.
//! Writes: the plants and the draw ([`FarPlacePass::plants`], [`FarPlacePass::draw`], read by
//! `FarPass`); ordered, the slots between its steps.

use ash::vk;

use super::{order, FarParams, FarRings, CAPACITY, PLACE_GROUP};
use crate::error::Result;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::recording::{self, PassSet, SceneSets};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, BufferDesc, Device, Guard};

/// Bytes of a placed plant (`FarPlant` of `far_field.glsl`).
const PLANT_BYTES: u64 = std::mem::size_of::<super::PlacedPlant>() as u64;

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
    /// With `--fade blend`: the order, the slots and the compaction.
    ordered: Option<Ordered>,
}

/// The ordered placement's own: the lattice's order (uploaded once), every point's slot, and the
/// compaction's pipeline.
struct Ordered {
    order: Buffer,
    staged: Buffer,
    compact: vk::Pipeline,
}

impl FarPlacePass {
    /// Build the pass for `params` (`points`: lattice points of its rings; `index_count`: the
    /// mesh's indices a plant); `ordered`: far to near, for `rings` (`--fade blend`).
    pub fn new(
        device: &Device,
        (sets, constants): (SceneSets, &Specialization),
        scene: &SceneGpu,
        (params, rings, ordered): (FarParams, &FarRings, bool),
        (points, index_count): (u32, u32),
    ) -> Result<Self> {
        let name = "far placement";
        let (place, compact) = (shaders::FAR_PLACE_ORDERED_COMP, shaders::FAR_ORDER_COMP);
        let spirv = if ordered { place } else { shaders::FAR_PLACE_COMP }.code(device.profile);
        let size = std::mem::size_of::<FarParams>() as u64;
        let uniforms = Guard::new(device, PassUniforms::new(device, name, size, sets.frames)?);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let plants = Guard::new(
            device,
            // Read back by `Renderer::far_plants`.
            Buffer::new(
                device,
                &BufferDesc::gpu_only(
                    "far plants",
                    PLANT_BYTES * u64::from(CAPACITY),
                    storage | vk::BufferUsageFlags::TRANSFER_SRC,
                ),
            )?,
        );
        let usage = storage
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let draw = Guard::new(device, Buffer::new(device, &BufferDesc::gpu_only("far draw", 20, usage))?);
        let mut staged = Guard::new(device, Vec::new());
        if ordered {
            let bytes = PLANT_BYTES * u64::from(CAPACITY);
            staged.push(Buffer::new(device, &BufferDesc::gpu_only("far slots", bytes, storage))?);
            let mut batch = UploadBatch::new(device);
            let list = order::far_to_near(rings);
            staged.push(batch.buffer("far order", &list, storage, &[Access::ComputeShaderRead])?);
            batch.submit()?;
        }
        let stages: Vec<(&str, &[u8])> = match ordered {
            true => vec![(name, spirv), ("far order", compact.code(device.profile))],
            false => vec![(name, spirv)],
        };
        let set = PassSet::new(device, &sets.desc(name, &stages), |slot| {
            let mut named = vec![
                ("FarParamsBlock", uniforms.resource(slot)),
                ("FarPlants", Descriptor::Buffer(plants.descriptor())),
                ("FarDraw", Descriptor::Buffer(draw.descriptor())),
            ];
            if let [slots, order] = &staged[..] {
                named.push(("FarStaged", Descriptor::Buffer(slots.descriptor())));
                named.push(("FarOrder", Descriptor::Buffer(order.descriptor())));
            }
            named
        })?;
        let set = Guard::new(device, set);
        let pipeline = Guard::new(device, pipeline::compute(device, name, spirv, set.layout, &constants.named())?);
        let ordered = match ordered {
            true => {
                let code = compact.code(device.profile);
                let compact = pipeline::compute(device, "far order", code, set.layout, &constants.named())?;
                let [staged, order]: [Buffer; 2] = staged.take().try_into().ok().expect("two buffers");
                Some(Ordered { order, staged, compact })
            }
            false => None,
        };
        Ok(Self {
            pipeline: pipeline.take(),
            set: set.take(),
            uniforms: uniforms.take(),
            params,
            plants: plants.take(),
            draw: draw.take(),
            points,
            index_count,
            ground: [scene.ground.texels.raw, scene.ground.cover.0.raw],
            ordered,
        })
    }

    /// The plants it writes.
    pub fn plants(&self) -> vk::DescriptorBufferInfo {
        self.plants.descriptor()
    }

    /// The slots of the ordered placement, written before their first read in a frame.
    pub fn staged(&self) -> Option<vk::Buffer> {
        self.ordered.as_ref().map(|ordered| ordered.staged.raw)
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
        let reset = Declaration::compute().step("reset").buffer(self.draw.raw, Access::TransferWrite).step("place");
        let placed = reset.buffer(self.ground[0], fetch).buffer(self.ground[1], fetch);
        let Some(ordered) = &self.ordered else {
            let appended = placed
                .buffer(self.draw.raw, Access::ComputeShaderRead)
                .buffer(self.draw.raw, Access::ComputeShaderWrite)
                .buffer(self.plants.raw, Access::ComputeShaderWrite);
            return Some(appended);
        };
        let declaration = placed
            .buffer(ordered.order.raw, Access::ComputeShaderRead)
            .buffer(ordered.staged.raw, Access::ComputeShaderWrite)
            .step("order")
            .buffer(ordered.staged.raw, Access::ComputeShaderRead)
            .buffer(self.draw.raw, Access::ComputeShaderWrite)
            .buffer(self.plants.raw, Access::ComputeShaderWrite);
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
        let (pipeline, groups) = match (ctx.step, &self.ordered) {
            (2, Some(ordered)) => (ordered.compact, 1),
            _ => (self.pipeline, self.points.div_ceil(PLACE_GROUP)),
        };
        // SAFETY: as above; both sets and the pipeline are bound (the compaction's layout is the
        // placement's); the graph put the step's barriers before it.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
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
            if let Some(ordered) = self.ordered {
                crate::vk::live::destroyed(ordered.compact);
                device.raw.destroy_pipeline(ordered.compact, None);
                ordered.order.destroy(device);
                ordered.staged.destroy(device);
            }
        }
    }
}
