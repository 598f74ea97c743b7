//! The far field's draw (`shaders/far_field/far.vert`, `far.frag`): after the blades, one
//! `vkCmdDrawIndexedIndirect` of the placed plants (its instance count the placement's), the
//! plant's rectangles from an index list of one plant, each instance one plant.
//!
//! Reads: the placed plants and their draw, the atlas (every level, sampled), the ground, this
//! frame's wind at the cluster corners and the emitters (the lean), its parameters; where the
//! blades read the pressed map (a response with pose records), its cells and its frame block
//! (after the parameters, in the pass's one uniform block), marked on frames with colliders or
//! cuts and until they recover. Writes: the
//! scene's colour and depth (opaque, depth-tested: the dither needs no order). With `--fade
//! blend`, the colour alone: blended with premultiplied alpha into the linear scene, the plants
//! in the placement's far-to-near order and each plant's rectangles far to near (the shaders'
//! variant `blend`), depth-tested against the blades and the ground; the pipeline writes no depth
//! (the attachment's store still counts as a write to the barriers).

use ash::vk;

use std::rc::Rc;

use super::atlas::Atlas;
use super::{pieces, plant_indices, FarFade, FarField, FarParams};
use crate::error::Result;
use crate::render::animation::pressed::MapReader;
use crate::render::graph::{Declaration, Pass, PassContext, PassUniforms};
use crate::render::passes::{self, PipelineTarget};
use crate::render::recording::{PassSet, SceneSets};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::upload::UploadBatch;
use crate::vk::{pipeline, Access, Buffer, Device, Guard, Resource};

/// The draw's pipeline, its set and uniforms, its index list and what it reads.
pub struct FarPass {
    pipeline: vk::Pipeline,
    set: PassSet,
    uniforms: PassUniforms,
    params: FarParams,
    indices: Buffer,
    /// The placement's plants and draw.
    placed: (vk::Buffer, vk::Buffer),
    atlas: Vec<Resource>,
    /// Its share of the atlas: the last owner destroys it.
    owned: Rc<Atlas>,
    ground: [vk::Buffer; 2],
    /// Each frame's wind at the cluster corners.
    wind: Vec<vk::Buffer>,
    /// The pressed map, when there is one.
    pressed: Option<MapReader>,
}

/// Where the pressed map's frame block starts in the pass's uniform block: after the parameters,
/// at the largest storage-buffer offset alignment Vulkan allows.
const PRESSED_OFFSET: u64 = 256 * (std::mem::size_of::<FarParams>() as u64).div_ceil(256);

/// What the far pass is built from.
pub struct FarSetup<'a> {
    /// The scene pipelines' target.
    pub target: PipelineTarget,
    /// The scene's sets.
    pub sets: SceneSets<'a>,
    /// Specialization constants.
    pub constants: &'a Specialization,
    /// The scene on the GPU.
    pub scene: &'a SceneGpu,
    /// Each frame's corner buffer.
    pub wind: &'a [vk::Buffer],
    /// The pressed map, when the graph has one (`render::animation::pressed`).
    pub pressed: Option<MapReader>,
}

/// The draw's shaders: blended or dithered, reading a pressed map or not.
fn stages(blend: bool, pressed: bool) -> (crate::vk::profile::Shader, crate::vk::profile::Shader) {
    let vertex = if blend { shaders::FAR_BLEND_VERT } else { shaders::FAR_VERT };
    let fragment = match (blend, pressed) {
        (false, false) => shaders::FAR_FRAG,
        (true, false) => shaders::FAR_BLEND_FRAG,
        (false, true) => shaders::FAR_PRESSED_FRAG,
        (true, true) => shaders::FAR_BLEND_PRESSED_FRAG,
    };
    (vertex, fragment)
}

/// The draw's set: its parameters and, with a pressed map, the map's frame block (both in the
/// pass's uniform block), the plants, the atlas's images and the map's cells.
fn pass_set(
    device: &Device,
    desc: &crate::render::recording::PassSetDesc,
    uniforms: &PassUniforms,
    (plants, atlas): (vk::DescriptorBufferInfo, &super::atlas::AtlasHandles),
    pressed: Option<&MapReader>,
) -> Result<PassSet> {
    PassSet::new(device, desc, |slot| {
        let block = |offset, range| vk::DescriptorBufferInfo { offset, range, ..uniforms.descriptor(slot) };
        let params = block(0, std::mem::size_of::<FarParams>() as u64);
        let mut named = vec![
            ("FarParamsBlock", Descriptor::Buffer(params)),
            ("FarPlants", Descriptor::Buffer(plants)),
            ("far_atlas", atlas.sampled(0)),
            ("far_heights", atlas.sampled(1)),
        ];
        if let Some(map) = pressed {
            named.push(map.resource());
            named.push(("PressedFrame", Descriptor::Buffer(block(PRESSED_OFFSET, MapReader::FRAME_BYTES))));
        }
        named
    })
}

impl FarPass {
    /// Build the draw of `mesh` over the plants and the draw the placement writes (`placed`),
    /// textured by `atlas`, meeting the blades by `fade`.
    pub fn new(
        device: &Device,
        setup: &FarSetup,
        (placed, owned): ((vk::DescriptorBufferInfo, vk::Buffer), Rc<Atlas>),
        (mesh, fade): (FarField, FarFade),
        params: FarParams,
    ) -> Result<Self> {
        let name = "far field";
        // Its own share of the atlas (with the bake's passes when it is baked in this graph).
        let owned = Guard::new(device, owned);
        let atlas = owned.handles();
        let blend = fade == FarFade::Blend;
        let pressed = setup.pressed.clone();
        let (vertex, fragment) = stages(blend, pressed.is_some());
        let (vertex, fragment) = (vertex.code(device.profile), fragment.code(device.profile));
        let size = match pressed {
            Some(_) => PRESSED_OFFSET + MapReader::FRAME_BYTES,
            None => std::mem::size_of::<FarParams>() as u64,
        };
        let uniforms = Guard::new(device, PassUniforms::new(device, name, size, setup.sets.frames)?);
        let stages = [("far vertex", vertex), ("far fragment", fragment)];
        let set = pass_set(device, &setup.sets.desc(name, &stages), &uniforms, (placed.0, &atlas), pressed.as_ref())?;
        let set = Guard::new(device, set);
        let mut batch = UploadBatch::new(device);
        let list = plant_indices(pieces(mesh, fade));
        let indices = batch.buffer("far indices", &list, vk::BufferUsageFlags::INDEX_BUFFER, &[Access::IndexRead])?;
        // Not submitted yet: the batch waits for its submission, or never submits.
        let indices = Guard::new(device, indices);
        batch.submit()?;
        let target = setup.target;
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name,
                vertex,
                fragment,
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                // The rectangles are seen from both sides.
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: !blend,
                color_format: target.color,
                depth_format: target.depth,
                layout: set.layout,
                constants: &setup.constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: if blend { pipeline::Blend::PremultipliedAlpha } else { pipeline::Blend::Opaque },
            },
        )?;
        let scene = setup.scene;
        Ok(Self {
            pipeline,
            set: set.take(),
            uniforms: uniforms.take(),
            params,
            indices: indices.take(),
            placed: (placed.0.buffer, placed.1),
            atlas: atlas.levels().collect(),
            owned: owned.take(),
            ground: [scene.ground.texels.raw, scene.ground.cover.0.raw],
            wind: setup.wind.to_vec(),
            pressed,
        })
    }
}

impl Pass for FarPass {
    fn name(&self) -> &'static str {
        "far field"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fetch = ctx.device.profile.vertex_fetch();
        // Blended, the pipeline tests depth without writing it, but the attachment's store (kept for
        // the passes after it) is a write: declared as one.
        let rendering = passes::scene_rendering(ctx, self.pipeline, true, false);
        let mut declaration = Declaration::graphics(rendering)
            .buffer(self.placed.0, Access::VertexShaderStorageRead)
            .buffer(self.placed.1, Access::IndirectCommandRead)
            .buffer(self.indices.raw, Access::IndexRead)
            .buffer(self.ground[0], fetch)
            .buffer(self.ground[1], fetch)
            .buffer(self.wind[ctx.slot], Access::VertexShaderStorageRead);
        for &level in &self.atlas {
            declaration = declaration.uses(level, Access::FragmentShaderSampledRead);
        }
        if let Some(map) = &self.pressed {
            declaration = declaration.buffer(map.cells, Access::FragmentShaderStorageRead);
        }
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.set.layout, self.pipeline);
        self.set.bind(device, cmd, vk::PipelineBindPoint::GRAPHICS, ctx.slot);
        // SAFETY: cmd is recording inside this pass's rendering instance; the sets and the
        // pipeline are bound; the placement wrote the draw before this pass (the graph's barrier).
        unsafe {
            device.raw.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            device.raw.cmd_draw_indexed_indirect(cmd, self.placed.1, 0, 1, 20);
        }
        Ok(())
    }

    fn uniforms(&self, _ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        let mut bytes = bytemuck::bytes_of(&self.params).to_vec();
        if let Some(map) = &self.pressed {
            bytes.resize(PRESSED_OFFSET as usize, 0);
            bytes.extend(map.frame_bytes(Default::default()));
        }
        Some((&self.uniforms, bytes))
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            self.set.destroy(device);
            self.uniforms.destroy(device);
            self.indices.destroy(device);
            crate::vk::Destroy::destroy(self.owned, device);
        }
    }
}
