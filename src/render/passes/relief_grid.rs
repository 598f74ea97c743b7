//! Relief-grid pass (a block field's): the ground's clipmap (`render::ground_clipmap`), its levels
//! the levels of one camera grid (`render::camera_grid`), first in the frame. When O's move takes
//! a level's window to another place on its lattice, one compute dispatch per such level
//! evaluates the relief (a sum of sine waves, `scene::field::Relief`) at the vertices that entered
//! it, each in the slot of its world vertex (`shaders/terrain/relief_grid.comp`): the relief's
//! height, the next level's mesh's height there and the normal, each a function of the world
//! vertex alone, in whole half-metres on the world's period, so the vertices a scroll keeps are
//! those a fresh fill writes. The terrain pass draws the levels from it, the cull's count pass
//! sets each candidate's root on it, and the blades' lighting takes the ground's normal under
//! each root from it, through `ground_vertex` (`shaders/common/field.glsl`), which finds the
//! vertex's slot from its window's toroidal base in the frame's uniforms and applies the morph.
//! Writes `SceneGpu::relief_grid`; the graph orders this frame's write after the previous frame's
//! reads, and each level's fill after the one before (a step each).
//!
//! A frame whose windows are the last filled ones records no dispatch (level 0's window moves
//! once the camera has gone 16 of its cells, 32 m at 2 m cells). The pass still declares its
//! write, so the graph's barriers are those of a frame that writes. A change of the clipmap (the
//! view distance) or of the relief refills it, as does the frame after one recorded but not run
//! (`Pass::frame_dropped`). A block field is drawn only through the cull, whose frames are
//! recorded anew each time (no `Prerecorded` replay of an old recording).

use std::cell::{Cell, RefCell};

use ash::vk;
use glam::IVec2;

use crate::error::{Error, Result};
use crate::render::camera_grid::{self, CameraGrid, Scroll};
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::ground_clipmap::{self, Clipmap};
use crate::render::recording;
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::{pipeline, Access, Device, Guard};

/// The compute pipeline, its layout (set 0 and the fill's push constants) and the grid it fills.
pub struct ReliefGridPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    buffer: vk::Buffer,
    /// The windows the buffer holds.
    grid: RefCell<CameraGrid>,
    /// What the grid's values are a function of besides the vertex.
    source: Cell<Option<Source>>,
    /// This frame's fills, one step each, planned by `declare` (or why they could not be).
    fills: RefCell<std::result::Result<Vec<Scroll>, String>>,
}

/// The clipmap's level-0 step and levels and the relief's waves, from the frame's uniforms: a
/// change refills the grid.
#[derive(Clone, Copy, PartialEq)]
struct Source {
    clipmap: (f32, u32),
    waves: [[f32; 4]; 8],
    cycles: [[i32; 4]; 4],
}

impl Source {
    fn of(uniforms: &FrameUniforms) -> Self {
        Self {
            clipmap: (uniforms.terrain.x, uniforms.relief_grid.z.max(1)),
            waves: uniforms.relief_waves.map(|w| w.to_array()),
            cycles: uniforms.relief_cycles.map(|c| c.to_array()),
        }
    }

    fn clipmap(&self) -> Clipmap {
        Clipmap { step: self.clipmap.0, levels: self.clipmap.1 }
    }
}

impl ReliefGridPass {
    /// Build the pipeline on a layout of its own (set 0 of `set_layout` and the fill's push
    /// constants); `None` for a stored field (its terrain is the uploaded `heights`).
    pub fn new(
        device: &Device,
        set_layout: vk::DescriptorSetLayout,
        constants: &Specialization,
        scene: &SceneGpu,
    ) -> Result<Option<Self>> {
        let Some(buffer) = scene.relief_grid_read() else {
            return Ok(None);
        };
        // Any clipmap: the shape is remade for the frame's before the first fill.
        let grid = CameraGrid::new(Clipmap { step: 1.0, levels: 1 }.shape()).map_err(Error::Internal)?;
        let range = camera_grid::push_constant_range();
        let layout = Guard::new(device, pipeline::layout(device, "relief grid layout", &[set_layout], &[range])?);
        let spirv = shaders::RELIEF_GRID_COMP.code(device.profile);
        let pipeline = pipeline::compute(device, "relief grid", spirv, *layout, &constants.named())?;
        let (grid, source, fills) = (RefCell::new(grid), Cell::new(None), RefCell::new(Ok(Vec::new())));
        Ok(Some(Self { pipeline, layout: layout.take(), buffer, grid, source, fills }))
    }
}

impl ReliefGridPass {
    /// Move each level's window to this frame's (O's cell's) and return the fills of the levels
    /// whose window moved: the vertices that entered, or every vertex of a level not filled yet.
    fn plan(&self, uniforms: &FrameUniforms) -> std::result::Result<Vec<Scroll>, String> {
        let source = Source::of(uniforms);
        let clipmap = source.clipmap();
        let mut grid = self.grid.borrow_mut();
        if self.source.get() != Some(source) {
            *grid = CameraGrid::new(clipmap.shape()).map_err(|e| format!("the ground's clipmap {clipmap:?}: {e}"))?;
            self.source.set(Some(source));
        }
        let cell = IVec2::new(uniforms.field_cells.x, uniforms.field_cells.y);
        let windows = clipmap.windows(cell);
        Ok((0..clipmap.levels)
            .filter_map(|level| grid.scroll_to(level, ground_clipmap::grid_window(windows[level as usize])))
            .collect())
    }
}

impl Pass for ReliefGridPass {
    fn name(&self) -> &'static str {
        "relief grid"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fills = self.plan(ctx.uniforms);
        let count = fills.as_ref().map_or(1, Vec::len);
        let write = Access::ComputeShaderWrite;
        let declaration = (1..count.max(1))
            .fold(Declaration::compute().buffer(self.buffer, write), |d, _| d.then().buffer(self.buffer, write));
        *self.fills.borrow_mut() = fills;
        Some(declaration)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let fills = self.fills.borrow();
        let fills = fills.as_ref().map_err(|e| Error::Internal(e.clone()))?;
        let Some(scroll) = fills.get(ctx.step) else {
            return Ok(());
        };
        let device = ctx.device;
        let dims = self.grid.borrow().shape().dims;
        recording::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        camera_grid::record_fill(device, cmd, (self.layout, self.pipeline), scroll, dims);
        Ok(())
    }

    fn frame_dropped(&self) {
        // The dispatch may not have run: the next frame fills the grid whole.
        self.grid.borrow_mut().invalidate();
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            crate::vk::live::destroyed(self.pipeline);
            device.raw.destroy_pipeline(self.pipeline, None);
            crate::vk::live::destroyed(self.layout);
            device.raw.destroy_pipeline_layout(self.layout, None);
        }
    }
}
