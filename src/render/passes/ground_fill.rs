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
use crate::render::recording::{self, PassSet, PassSetDesc};
use crate::render::scene_gpu::SceneGpu;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::{Resource, SetLayout};
use crate::vk::{pipeline, Access, Destroy, Device, Guard};

/// The compute pipeline, its layout (set 0 and the fill's push constants, and the source's own
/// set when its fill reads buffers of its own) and the grid it fills.
pub struct GroundFillPass {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    /// The source's own set (`GroundSource::buffers`, `SET_PASS`), if it has buffers.
    own: Option<PassSet>,
    /// Those buffers, read each fill.
    reads: Vec<vk::Buffer>,
    /// The clipmap's texels and cover, written.
    buffer: vk::Buffer,
    cover: vk::Buffer,
    fill: Box<dyn GroundFill>,
    /// The windows the buffer holds.
    grid: RefCell<CameraGrid>,
    /// What the texels are a function of besides the vertex, when last filled.
    key: RefCell<Option<Vec<u32>>>,
    /// This frame's fills, one step each, planned by `declare` (or why they could not be).
    fills: RefCell<std::result::Result<Vec<Scroll>, String>>,
}

impl GroundFillPass {
    /// Build the pipeline of the scene's ground fill on a layout of its own (set 0 of `sets`,
    /// the fill's push constants, and with the source's buffers its own set after `sets`, one per
    /// frame in flight of `frames`); `None` for a ground uploaded once (a stored terrain).
    pub fn new(
        device: &Device,
        (sets, frames): ([&SetLayout; 2], usize),
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
        let spirv = fill.shader().code(device.profile);
        let extra = &scene.ground.extra;
        // The source's buffers in its own set, by the names its fill shader declares.
        let own = match extra.is_empty() {
            true => None,
            false => {
                let shaders = [(fill.shader().path, spirv)];
                let desc =
                    PassSetDesc { name: "ground fill", shaders: &shaders, before: &sets, push: &[range], frames };
                let named = |_| extra.iter().map(|(name, b)| (*name, Resource::Buffer(b.descriptor()))).collect();
                Some(Guard::new(device, PassSet::new(device, &desc, named)?))
            }
        };
        // With its own set, the set's pipeline layout (destroyed with it); else one of its own.
        let plain = match &own {
            Some(_) => None,
            None => Some(Guard::new(device, pipeline::layout(device, "ground fill layout", &[sets[0].raw], &[range])?)),
        };
        let layout = own.as_ref().map_or_else(|| **plain.as_ref().expect("made"), |set| set.layout);
        let pipeline = pipeline::compute(device, "ground fill", spirv, layout, &constants.named())?;
        let (grid, key, fills) = (RefCell::new(grid), RefCell::new(None), RefCell::new(Ok(Vec::new())));
        let reads = extra.iter().map(|(_, b)| b.raw).collect();
        let (_, own, buffer) = (plain.map(Guard::take), own.map(Guard::take), scene.ground.texels.raw);
        let cover = scene.ground.cover.0.raw;
        Ok(Some(Self { pipeline, layout, own, reads, buffer, cover, fill, grid, key, fills }))
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
        let first = self.reads.iter().fold(Declaration::compute(), |d, &b| d.buffer(b, Access::ComputeShaderRead));
        let declaration = (1..count.max(1)).fold(first.buffer(self.buffer, write).buffer(self.cover, write), |d, _| {
            let step = self.reads.iter().fold(d.then(), |d, &b| d.buffer(b, Access::ComputeShaderRead));
            step.buffer(self.buffer, write).buffer(self.cover, write)
        });
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
        if let Some(own) = &self.own {
            own.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        }
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
            match self.own {
                Some(own) => own.destroy(device),
                None => {
                    crate::vk::live::destroyed(self.layout);
                    device.raw.destroy_pipeline_layout(self.layout, None);
                }
            }
        }
    }
}
