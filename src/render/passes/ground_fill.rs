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
//! After the levels' fills, one more step writes the moved levels' tiles (`render::ground::tiles`,
//! `shaders/terrain/ground_tiles.comp`): each tile's lowest and highest height and most cover,
//! which the cull bounds its cells by.
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
use bytemuck::{Pod, Zeroable};
use glam::UVec4;

use crate::error::{Error, Result};
use crate::render::camera_grid::{self, CameraGrid, Scroll};
use crate::render::gpu_constants as gpu;
use crate::render::graph::{Declaration, Pass, PassContext};
use crate::render::ground::{tiles, GroundFill};
use crate::render::recording::{self, PassSet, PassSetDesc};
use crate::render::scene_gpu::SceneGpu;
use crate::render::shaders;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::{Resource, SetLayout};
use crate::vk::{pipeline, Access, Destroy, Device, Guard};

/// The compute pipeline, its layout (set 0 and the fill's push constants, and the source's own
/// set when its fill reads buffers of its own) and the grid it fills.
pub struct GroundFillPass {
    pipeline: vk::Pipeline,
    /// The tiles' pipeline (`ground_tiles.comp`), on the same layout.
    tiles: vk::Pipeline,
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
        let pipeline = Guard::new(device, pipeline::compute(device, "ground fill", spirv, layout, &constants.named())?);
        let tiles_spirv = shaders::GROUND_TILES_COMP.code(device.profile);
        let tiles = pipeline::compute(device, "ground tiles", tiles_spirv, layout, &constants.named())?;
        let pipeline = pipeline.take();
        let (grid, key, fills) = (RefCell::new(grid), RefCell::new(None), RefCell::new(Ok(Vec::new())));
        let reads = extra.iter().map(|(_, b)| b.raw).collect();
        let (_, own, buffer) = (plain.map(Guard::take), own.map(Guard::take), scene.ground.texels.raw);
        let cover = scene.ground.cover.0.raw;
        Ok(Some(Self { pipeline, tiles, layout, own, reads, buffer, cover, fill, grid, key, fills }))
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

impl GroundFillPass {
    /// The tiles of the levels `fills` moved, in a clipmap of `cells` cells a level: one
    /// invocation a tile.
    fn record_tiles(&self, device: &Device, cmd: vk::CommandBuffer, fills: &[Scroll], cells: u32) {
        let mut push = TilesPush::zeroed();
        for (k, scroll) in fills.iter().enumerate() {
            push.levels[k / 4][k % 4] = scroll.level;
        }
        let per = tiles::per_side(cells).pow(2);
        push.count = UVec4::new(fills.len() as u32, per, 0, 0);
        let groups = (push.count.x * per).div_ceil(gpu::CAMERA_GRID_GROUP);
        // SAFETY: cmd is recording outside a rendering instance; the layout's compute push range
        // (`FillPush`'s) holds `TilesPush` at offset 0.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.tiles);
            device.raw.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(&push),
            );
            device.raw.cmd_dispatch(cmd, groups, 1, 1);
        }
    }
}

/// The tiles' push constants (`Tiles` in `shaders/terrain/ground_tiles.comp`): the levels to tile,
/// four a vector, and x how many, y the tiles of a level.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct TilesPush {
    levels: [UVec4; 4],
    count: UVec4,
}

const _: () = assert!(
    std::mem::size_of::<TilesPush>() <= std::mem::size_of::<camera_grid::FillPush>()
        && gpu::CAMERA_GRID_MAX_LEVELS <= 16
        && gpu::FIELD_TERRAIN_CELLS.is_multiple_of(gpu::GROUND_TILE_CELLS)
);

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
        // The tiles: the filled vertices and covers read, the tile texels written.
        let read = Access::ComputeShaderRead;
        let tiles = declaration.then().buffer(self.buffer, read).buffer(self.cover, read).buffer(self.buffer, write);
        *self.fills.borrow_mut() = fills;
        Some(tiles)
    }

    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()> {
        let fills = self.fills.borrow();
        let fills = fills.as_ref().map_err(|e| Error::Internal(e.clone()))?;
        let device = ctx.device;
        let dims = self.grid.borrow().shape().dims;
        recording::bind_scene_set(device, ctx, cmd, self.layout, vk::PipelineBindPoint::COMPUTE);
        if let Some(own) = &self.own {
            own.bind(device, cmd, vk::PipelineBindPoint::COMPUTE, ctx.slot);
        }
        match fills.get(ctx.step) {
            Some(scroll) => camera_grid::record_fill(device, cmd, (self.layout, self.pipeline), scroll, dims),
            None => self.record_tiles(device, cmd, fills, dims.x - 1),
        }
        Ok(())
    }

    fn frame_dropped(&self) {
        // The dispatch may not have run: the next frame fills the grid whole.
        self.grid.borrow_mut().invalidate();
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe {
            for pipeline in [self.pipeline, self.tiles] {
                crate::vk::live::destroyed(pipeline);
                device.raw.destroy_pipeline(pipeline, None);
            }
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
