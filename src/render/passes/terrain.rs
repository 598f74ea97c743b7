//! Terrain pass: the ground's clipmap (`render::ground`), an indexed triangle list over a level's
//! grid vertices pulled from its texels (a relief's filled by `passes::ground_fill`, added with
//! it and run before it), one draw per run of chunks in view (`render::terrain_chunks`) per level
//! but the finer level's square, the level the draw's first instance. The first pass that draws: it clears colour to the sky and depth to the far plane
//! (0, reversed Z).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::render::graph::{Declaration, Load, Pass, PassContext};
use crate::render::passes::{self, PipelineTarget};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::render::terrain_chunks::{self, GridPlacement, TerrainChunk};
use crate::render::uniforms::FrameUniforms;
use crate::vk::{pipeline, Access, Device};

/// The terrain pipeline and what it draws.
pub struct TerrainPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    /// The ground's clipmap (`render::ground`), whose texels and cover the vertex shader reads.
    ground: [vk::Buffer; 2],
    indices: vk::Buffer,
    /// A level's chunks, each a range of `indices`.
    chunks: Vec<TerrainChunk>,
    /// The ground's height range.
    height_range: (f32, f32),
    /// Where it leaves the triangles of the chunks it drew (`GroundGpu::drawn`).
    drawn: Arc<AtomicU64>,
    sky: [f32; 4],
}

impl TerrainPass {
    /// Build the pipeline; `sky` is the clear colour as the target stores it.
    pub fn new(
        device: &Device,
        target: PipelineTarget,
        constants: &Specialization,
        scene: &SceneGpu,
        sky: [f32; 4],
    ) -> Result<Self> {
        let pipeline = pipeline::graphics(
            device,
            &pipeline::GraphicsDesc {
                name: "terrain",
                vertex: shaders::TERRAIN_VERT.code(device.profile),
                fragment: shaders::TERRAIN_FRAG.code(device.profile),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull: vk::CullModeFlags::NONE,
                polygon: target.polygon,
                depth_compare: vk::CompareOp::GREATER,
                depth_write: true,
                color_format: target.color,
                depth_format: target.depth,
                layout: target.layout,
                constants: &constants.named(),
                vertex_stride: 0,
                samples: target.samples,
                blend: pipeline::Blend::Opaque,
            },
        )?;
        Ok(Self {
            pipeline,
            layout: target.layout,
            ground: [scene.ground.texels.raw, scene.ground.cover.0.raw],
            indices: scene.ground.indices.raw,
            chunks: terrain_chunks::chunks(scene.ground.source.cells(), scene.ground.source.chunk_cells()),
            height_range: scene.ground.source.height_range(),
            drawn: Arc::clone(&scene.ground.drawn),
            sky,
        })
    }

    /// This frame's draws: per level of the ground's clipmap (terrain.vert places them the same
    /// way) the runs of chunks in view, and the level.
    fn draws(&self, uniforms: &FrameUniforms) -> Vec<(u32, (u32, u32))> {
        let view_proj = &uniforms.view_proj;
        let levels = uniforms.ground.z.max(1);
        let mut draws = Vec::new();
        for level in 0..levels {
            let window = uniforms.ground_levels[level as usize];
            let placement = GridPlacement { offset: [window.x, window.y], step: window.z, heights: self.height_range };
            // The finer level's square, whole cells of this level's (`ground_clipmap::Clipmap::hole`).
            let hole = (level > 0).then(|| {
                let finer = uniforms.ground_levels[level as usize - 1];
                let cells = (finer.truncate().truncate() - window.truncate().truncate()) / window.z;
                [cells.x.round() as u32, cells.y.round() as u32]
            });
            let runs = terrain_chunks::visible_runs(&self.chunks, &placement, view_proj, hole);
            draws.extend(runs.into_iter().map(|run| (level, run)));
        }
        draws
    }

    /// Triangles the pass drew in the last frame it recorded: the chunks in view.
    pub fn triangles(scene: &SceneGpu) -> u64 {
        scene.ground.drawn.load(Ordering::Relaxed)
    }
}

impl Pass for TerrainPass {
    fn name(&self) -> &'static str {
        "terrain"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let mut rendering = passes::scene_rendering(ctx, self.pipeline, true, false);
        let clear_color = vk::ClearValue { color: vk::ClearColorValue { float32: self.sky } };
        let clear_depth = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 } };
        rendering.color.as_mut().expect("scene colour").load = Load::Clear(clear_color);
        rendering.depth.as_mut().expect("scene depth").load = Load::Clear(clear_depth);
        let fetch = ctx.device.profile.vertex_fetch();
        let declaration = Declaration::graphics(rendering).buffer(self.ground[0], fetch).buffer(self.ground[1], fetch);
        Some(declaration.buffer(self.indices, Access::IndexRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        // SAFETY: cmd is recording inside this pass's rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_index_buffer(cmd, self.indices, 0, vk::IndexType::UINT32);
        }
        let mut indices = 0;
        for (level, (first, count)) in self.draws(ctx.uniforms) {
            // SAFETY: as above; the run lies inside the index buffer (`chunks`).
            unsafe { device.raw.cmd_draw_indexed(cmd, count, 1, first, 0, level) };
            indices += u64::from(count);
        }
        self.drawn.store(indices / 3, Ordering::Relaxed);
        Ok(())
    }

    fn replay_key(&self, ctx: &PassContext) -> Option<u64> {
        // The chunks in view are chosen on the CPU: a replay holds while they are the same.
        use std::hash::{Hash, Hasher};
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        self.draws(ctx.uniforms).hash(&mut hasher);
        Some(hasher.finish())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None)
        };
    }
}
