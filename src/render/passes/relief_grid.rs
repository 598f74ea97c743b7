//! Relief-grid pass (a block field's): one compute dispatch, first in the frame, that evaluates the
//! relief (a sum of sine waves, `scene::field::Relief`) at every vertex of the terrain grid around
//! O, height and normal (`shaders/terrain/relief_grid.comp`). The terrain pass draws the grid from it, the
//! cull's count pass sets each candidate's root on it, and the blades' lighting takes the terrain
//! normal under each root from it: a texel fetch per corner instead of the relief's eight waves
//! per terrain vertex, candidate root and drawn blade. Writes `SceneGpu::relief_grid`; the graph
//! orders this frame's write after the previous frame's reads.
//!
//! The grid depends only on where it lies (O's cell, the cell edge and the offset that keeps it on
//! the world's lattice) and on the relief, so a frame whose values match the last frame's that
//! dispatched records no dispatch: the grid in the buffer is already this frame's (0.45 ms of the
//! unbounded default view's frame; the camera crosses a 4 m block, and the grid is recomputed, only
//! now and then). The pass still declares its write, so the graph's barriers are those of a frame
//! that writes. A frame that is recorded but not run (`Pass::frame_dropped`) forgets the key; a
//! block field is drawn only through the cull, whose frames are recorded anew each time (no
//! `Prerecorded` replay of an old recording).

use std::cell::Cell;

use ash::vk;

use crate::error::Result;
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::recording;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::uniforms::FrameUniforms;
use crate::vk::{pipeline, Access, Device};

/// The compute pipeline and the grid it writes.
pub struct ReliefGridPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    grid: vk::Buffer,
    /// The values the last recorded dispatch computed the grid for (`GridKey`).
    written: Cell<Option<GridKey>>,
}

/// What the grid is a function of, from the frame's uniforms: O's cell, the terrain grid's cell
/// edge and offset, the relief's waves and their phases at O.
#[derive(Clone, Copy, PartialEq)]
struct GridKey {
    cell: [i32; 2],
    terrain: [f32; 4],
    waves: [[f32; 4]; 8],
    phases: [[f32; 4]; 4],
}

impl GridKey {
    fn of(uniforms: &FrameUniforms) -> Self {
        Self {
            cell: [uniforms.field_cells.x, uniforms.field_cells.y],
            terrain: uniforms.terrain.to_array(),
            waves: uniforms.relief_waves.map(|w| w.to_array()),
            phases: uniforms.relief_phases.map(|p| p.to_array()),
        }
    }
}

impl ReliefGridPass {
    /// Build the pipeline on the scene pipeline layout; `None` for a stored field (its terrain is
    /// the uploaded `heights`).
    pub fn new(
        device: &Device,
        layout: vk::PipelineLayout,
        constants: &[u32],
        scene: &SceneGpu,
    ) -> Result<Option<Self>> {
        let Some(grid) = scene.relief_grid_read() else {
            return Ok(None);
        };
        let pipeline = pipeline::compute(
            device,
            "relief grid",
            shaders::RELIEF_GRID_COMP.code(device.profile),
            layout,
            constants,
        )?;
        Ok(Some(Self { pipeline, layout, grid, written: Cell::new(None) }))
    }
}

impl Pass for ReliefGridPass {
    fn name(&self) -> &'static str {
        "relief grid"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.grid, Access::ComputeShaderWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let key = GridKey::of(ctx.uniforms);
        if self.written.get() == Some(key) {
            return Ok(());
        }
        self.written.set(Some(key));
        let device = ctx.device;
        recording::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        let vertices = (gpu::FIELD_TERRAIN_CELLS + 1).pow(2);
        // SAFETY: cmd is recording outside a rendering instance; set 0 is bound.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_dispatch(cmd, vertices.div_ceil(gpu::RELIEF_GROUP), 1, 1);
        }
        Ok(())
    }

    fn frame_dropped(&self) {
        // The dispatch may not have run: the next frame computes the grid again.
        self.written.set(None);
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None)
        };
    }
}
