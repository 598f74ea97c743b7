//! Terrain pass: the height field, an indexed triangle list over its grid vertices pulled from the
//! heights buffer (a block field's from the relief grid, `passes::relief_grid`, added with it and
//! run before it), one draw per run of chunks in view (`render::terrain_chunks`). The first pass
//! that draws: it clears colour to the sky and depth to the far plane (0, reversed Z).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::render::field_gpu;
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
    heights: vk::Buffer,
    /// A block field's relief grid, which the vertex shader reads instead of `heights`.
    relief_grid: Option<vk::Buffer>,
    indices: vk::Buffer,
    /// The grid's chunks, each a range of `indices`.
    chunks: Vec<TerrainChunk>,
    /// A block field's grid (placed around O by `FrameUniforms::terrain`'s zw) or a stored one.
    blocks: bool,
    /// The terrain's height range.
    height_range: (f32, f32),
    /// Where it leaves the triangles of the chunks it drew (`SceneGpu::terrain_drawn`).
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
            heights: scene.heights.raw,
            relief_grid: scene.relief_grid_read(),
            indices: scene.terrain_indices.raw,
            chunks: terrain_chunks::chunks(scene.terrain_cells, scene.field.is_some()),
            blocks: scene.field.is_some(),
            height_range: scene.terrain_heights,
            drawn: Arc::clone(&scene.terrain_drawn),
            sky,
        })
    }

    /// Where this frame's grid lies (terrain.vert places it the same way).
    fn placement(&self, uniforms: &FrameUniforms) -> GridPlacement {
        let t = uniforms.terrain;
        let (offset, step) = if self.blocks { ([t.z, t.w], t.x) } else { ([t.x, t.x], t.y) };
        GridPlacement { offset, step, heights: self.height_range }
    }

    /// Triangles the pass drew in the last frame it recorded: the chunks in view.
    pub fn triangles(scene: &SceneGpu) -> u64 {
        scene.terrain_drawn.load(Ordering::Relaxed)
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
        let mut declaration = Declaration::graphics(rendering).buffer(self.heights, Access::VertexShaderStorageRead);
        if let Some(grid) = self.relief_grid {
            declaration = declaration.buffer(grid, ctx.device.profile.vertex_fetch());
        }
        Some(declaration.buffer(self.indices, Access::IndexRead))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let device = ctx.device;
        passes::bind_graphics(device, ctx, cmd, self.layout, self.pipeline);
        // SAFETY: cmd is recording inside this pass's rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_index_buffer(cmd, self.indices, 0, vk::IndexType::UINT32);
        }
        let placement = self.placement(ctx.uniforms);
        let mut indices = 0;
        // A block field's far chunks in cells of two steps, when the relief grid's odd vertices
        // morph onto them (`field_gpu::terrain_coarsens`).
        let coarse = self.blocks && field_gpu::terrain_coarsens(placement.step);
        let view_proj = &ctx.uniforms.view_proj;
        for (first, count) in terrain_chunks::visible_runs(&self.chunks, &placement, view_proj, coarse) {
            // SAFETY: as above; the run lies inside the index buffer (`chunks`).
            unsafe { device.raw.cmd_draw_indexed(cmd, count, 1, first, 0, 0) };
            indices += u64::from(count);
        }
        self.drawn.store(indices / 3, Ordering::Relaxed);
        Ok(())
    }

    fn replay_key(&self, ctx: &PassContext) -> Option<u64> {
        // The chunks in view are chosen on the CPU: a replay holds while they are the same.
        use std::hash::{Hash, Hasher};
        let placement = self.placement(ctx.uniforms);
        let coarse = self.blocks && field_gpu::terrain_coarsens(placement.step);
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        terrain_chunks::visible_runs(&self.chunks, &placement, &ctx.uniforms.view_proj, coarse).hash(&mut hasher);
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
