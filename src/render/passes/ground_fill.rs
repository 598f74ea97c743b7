//! Ground-fill pass: the ground's clipmap (`render::ground`) for a source the camera's moves fill
//! (`GroundSource::fill`, today a block field's relief), its levels the levels of one camera grid
//! (`render::camera_grid`), first in the frame. When O's move takes a level's window to another
//! place on its lattice, one compute dispatch per such level runs the source's fill shader
//! (`shaders/terrain/relief_fill.comp` for the relief) over the vertices that entered it, each in
//! the slot of its world vertex: what depends on the world vertex alone (height, the next level's
//! mesh there, the rise), so the vertices a scroll keeps are those a fresh fill writes. The
//! terrain pass draws the levels from it, the cull's count pass sets each candidate's root on it,
//! and the blades' lighting takes the ground's normal under each root from it, through
//! `shaders/common/ground.glsl`. Writes `GroundGpu::texels`; the graph orders this frame's write
//! after the previous frame's reads, and each level's fill after the one before (a step each).
//!
//! A frame whose windows are the last filled ones skips the pass (`declare` returns `None`: no
//! barrier, no dispatch, no timestamps); the relief's level 0 moves once the camera has gone 8 of
//! its cells, 16 m at 2 m cells. A change of what the
//! texels are a function of (`GroundFill::key`: the relief's clipmap and waves) refills every
//! level, as does the frame after one recorded but not run (`Pass::frame_dropped`). A block field
//! is drawn only through the cull, whose frames are recorded anew each time (no `Prerecorded`
//! replay of an old recording).

use std::cell::RefCell;

use ash::vk;

use crate::error::{Error, Result};
use crate::render::camera_grid::{self, CameraGrid, Scroll};
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::ground::GroundFill;
use crate::render::recording;
use crate::render::scene_gpu::SceneGpu;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::{pipeline, Access, Device, Guard};

/// The compute pipeline, its layout (set 0 and the fill's push constants) and the grid it fills.
pub struct GroundFillPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    buffer: vk::Buffer,
    fill: Box<dyn GroundFill>,
    /// The windows the buffer holds.
    grid: RefCell<CameraGrid>,
    /// What the texels are a function of besides the vertex, when last filled.
    key: RefCell<Option<Vec<u32>>>,
    /// This frame's fills, one step each, planned by `declare` (or why they could not be).
    fills: RefCell<std::result::Result<Vec<Scroll>, String>>,
}

impl GroundFillPass {
    /// Build the pipeline of the scene's ground fill on a layout of its own (set 0 of
    /// `set_layout` and the fill's push constants); `None` for a ground uploaded once (a stored
    /// terrain).
    pub fn new(
        device: &Device,
        set_layout: vk::DescriptorSetLayout,
        constants: &Specialization,
        scene: &SceneGpu,
    ) -> Result<Option<Self>> {
        let Some(fill) = scene.ground.source.fill() else {
            return Ok(None);
        };
        // Any shape: the grid is remade for the frame's before the first fill.
        let mut zeroed: FrameUniforms = bytemuck::Zeroable::zeroed();
        zeroed.ground_levels[0].z = 1.0;
        let grid = CameraGrid::new(fill.shape(&zeroed)).map_err(Error::Internal)?;
        let range = camera_grid::push_constant_range();
        let layout = Guard::new(device, pipeline::layout(device, "ground fill layout", &[set_layout], &[range])?);
        let spirv = fill.shader().code(device.profile);
        let pipeline = pipeline::compute(device, "ground fill", spirv, *layout, &constants.named())?;
        let (grid, key, fills) = (RefCell::new(grid), RefCell::new(None), RefCell::new(Ok(Vec::new())));
        Ok(Some(Self { pipeline, layout: layout.take(), buffer: scene.ground.texels.raw, fill, grid, key, fills }))
    }

    /// Move each level's window to this frame's and return the fills of the levels whose window
    /// moved: the vertices that entered, or every vertex of a level not filled yet.
    fn plan(&self, uniforms: &FrameUniforms) -> std::result::Result<Vec<Scroll>, String> {
        let key = self.fill.key(uniforms);
        let mut grid = self.grid.borrow_mut();
        if self.key.borrow().as_ref() != Some(&key) {
            let shape = self.fill.shape(uniforms);
            *grid = CameraGrid::new(shape).map_err(|e| format!("the ground's clipmap {shape:?}: {e}"))?;
            *self.key.borrow_mut() = Some(key);
        }
        let windows = self.fill.windows(uniforms);
        Ok(windows.into_iter().enumerate().filter_map(|(level, window)| grid.scroll_to(level as u32, window)).collect())
    }
}

impl Pass for GroundFillPass {
    fn name(&self) -> &'static str {
        "ground fill"
    }

    fn declare(&self, ctx: &PassContext) -> Option<Declaration> {
        let fills = self.plan(ctx.uniforms);
        // No window moved: nothing to write, and no barrier or timestamps to pay for.
        if fills.as_ref().is_ok_and(Vec::is_empty) {
            *self.fills.borrow_mut() = fills;
            return None;
        }
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
