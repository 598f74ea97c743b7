//! Relief-grid pass (a block field's): the terrain grid around O as a camera grid
//! (`render::camera_grid`, one level of (`FIELD_TERRAIN_CELLS` + 1)² vertices on the world's
//! lattice of the grid's step), first in the frame. When O moves to another block and the grid's
//! window moves on its lattice, one compute dispatch evaluates the relief (a sum of sine waves,
//! `scene::field::Relief`) at the window's vertices, each in the slot of its world vertex
//! (`shaders/terrain/relief_grid.comp`): the relief's height, the coarse mesh's height and the
//! normal, each a function of the world vertex alone. The terrain pass draws the grid from it, the
//! cull's count pass sets each candidate's root on it, and the blades' lighting takes the terrain
//! normal under each root from it, through `relief_vertex` (`shaders/common/field.glsl`), which finds the vertex's
//! slot from the window's toroidal base in the frame's uniforms and applies the terrain's morph.
//! Writes `SceneGpu::relief_grid`; the graph orders this frame's write after the previous frame's
//! reads.
//!
//! A frame whose window is the last filled one records no dispatch (the camera crosses a 4 m
//! block only now and then). A frame whose window moved fills it whole for now (`record` says
//! why), through the same fill a scroll of entered vertices uses. The pass still declares its
//! write, so the graph's barriers are those of a frame that writes. A change of the grid's step
//! (the view distance) or of the relief refills it, as does the frame after one recorded but not
//! run (`Pass::frame_dropped`). A
//! block field is drawn only through the cull, whose frames are recorded anew each time (no
//! `Prerecorded` replay of an old recording).

use std::cell::{Cell, RefCell};

use ash::vk;
use glam::IVec2;

use crate::error::{Error, Result};
use crate::render::camera_grid::{self, CameraGrid};
use crate::render::field_gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
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
    /// The window the buffer holds.
    grid: RefCell<CameraGrid>,
    /// What the grid's values are a function of besides the vertex.
    source: Cell<Option<Source>>,
}

/// The grid's step and the relief's waves, from the frame's uniforms: a change refills the grid.
#[derive(Clone, Copy, PartialEq)]
struct Source {
    step: f32,
    waves: [[f32; 4]; 8],
}

impl Source {
    fn of(uniforms: &FrameUniforms) -> Self {
        Self { step: uniforms.terrain.x, waves: uniforms.relief_waves.map(|w| w.to_array()) }
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
        // Any step: the shape is remade for the frame's step before the first fill.
        let grid = CameraGrid::new(field_gpu::relief_grid_shape(1.0)).map_err(Error::Internal)?;
        let range = camera_grid::push_constant_range();
        let layout = Guard::new(device, pipeline::layout(device, "relief grid layout", &[set_layout], &[range])?);
        let spirv = shaders::RELIEF_GRID_COMP.code(device.profile);
        let pipeline = pipeline::compute(device, "relief grid", spirv, *layout, &constants.named())?;
        Ok(Some(Self { pipeline, layout: layout.take(), buffer, grid: RefCell::new(grid), source: Cell::new(None) }))
    }
}

impl Pass for ReliefGridPass {
    fn name(&self) -> &'static str {
        "relief grid"
    }

    fn declare(&self, _: &PassContext) -> Option<Declaration> {
        Some(Declaration::compute().buffer(self.buffer, Access::ComputeShaderWrite))
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let uniforms = ctx.uniforms;
        let source = Source::of(uniforms);
        let mut grid = self.grid.borrow_mut();
        if self.source.get() != Some(source) {
            *grid = CameraGrid::new(field_gpu::relief_grid_shape(source.step)).map_err(Error::Internal)?;
            self.source.set(Some(source));
        }
        let cell = IVec2::new(uniforms.field_cells.x, uniforms.field_cells.y);
        let window = field_gpu::relief_grid_window(cell, source.step);
        if grid.window(0) == Some(window) {
            return Ok(());
        }
        // The whole window, not only the vertices that entered: the relief is evaluated relative
        // to this frame's O in f32, so a vertex filled under another O differs in its last bits,
        // and a scrolled grid would not draw the bit-identical picture a fresh renderer draws
        // (`tests/field.rs`). Filling only what enters waits for a fill exact in the world (the
        // relief's phases taken on the world period).
        grid.invalidate();
        let scroll = grid.scroll_to(0, window).expect("an empty grid fills");
        let device = ctx.device;
        recording::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        camera_grid::record_fill(device, cmd, (self.layout, self.pipeline), &scroll, grid.shape().dims);
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
