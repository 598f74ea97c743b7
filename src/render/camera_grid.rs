//! Camera-following grids: a fixed block of cells around the camera that scrolls by whole cells,
//! as the relief grid does today and as the wind's levels, the blade state store, the ground
//! clipmap, the fluid grid and the trampling map will. This module is the one place of their
//! addressing; `shaders/common/camera_grid.glsl` mirrors it for the GPU, and `shaders/common/shared.glsl`
//! holds the constants both read.
//!
//! - **Levels.** `levels` nested windows of `dims` cells each, level l's cells 2^l times level
//!   0's, every level centred on the camera: coarser with distance, the same memory per level.
//! - **2-D or 3-D.** `dims` is per axis; a 2-D grid over the ground has one cell along y.
//! - **World lattice, f64.** A cell is named by its integer index on the world's lattice of its
//!   level (`i64`, world position = index × cell edge, in f64), so a grid 100 km from the
//!   world's origin addresses as one at it. The GPU sees the window's first cell relative to the
//!   frame's origin O, a small f32 ([`CameraGrid::corner`]).
//! - **Toroidal addressing.** World cell `w` always sits in slot `w mod dims` of its level: when
//!   the window scrolls, cells that stay keep their slot and their value, and only the cells that
//!   enter are written, over the slots of those that left.
//! - **Whole-cell scrolling.** [`CameraGrid::scroll_to`] moves a level's window and returns the
//!   cells that entered as at most three disjoint boxes ([`Scroll`]); a move of a window or more,
//!   or a grid not filled yet, enters every cell.
//! - **Filling what enters.** On the CPU, [`Scroll::for_each_entered`] calls back with each
//!   entered cell; on the GPU, [`record_fill`] dispatches the grid's fill shader over them, its
//!   push constants the boxes ([`FillPush`], `CameraGridFill` in GLSL, read with
//!   `camera_grid_entered`).
//! - **Fixed memory.** [`GridShape::bytes`] is all a grid ever holds, whatever the distance the
//!   camera travels; the owner allocates it once, after the memory budget's check.
//!
//! A grid's values are to be a function of the world cell alone (the relief grid stores the
//! relief and its coarse mean, and applies the camera-relative terrain morph when it reads).
//! A temporal grid (a simulation's state kept in a ping-pong pair) shares one `CameraGrid`
//! between its two resources: on a scroll, the cells that enter are filled in the resource the
//! next step reads, before that step.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DVec3, I64Vec3, UVec3, UVec4, Vec3};

use crate::render::gpu_constants as gpu;
use crate::vk::Device;

/// The shape of a camera grid: fixed when it is made, and with it the memory it holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridShape {
    /// Cells per axis of each level (x, y up, z; a grid over the ground has 1 along y).
    pub dims: UVec3,
    /// Edge of a level-0 cell per axis, in metres.
    pub cell: DVec3,
    /// Nested levels, level l's cells 2^l times level 0's.
    pub levels: u32,
    /// Bytes per cell.
    pub texel_bytes: u32,
}

impl GridShape {
    /// Refuse a shape the addressing cannot hold: no cells, a level's slots past `u32`, or a cell
    /// edge that is not a finite length above 0.
    pub fn check(&self) -> Result<(), String> {
        if self.dims.min_element() == 0 || self.levels == 0 || self.texel_bytes == 0 {
            return Err(format!("a camera grid of {} cells × {} levels is empty", self.dims, self.levels));
        }
        if self.levels > gpu::CAMERA_GRID_MAX_LEVELS {
            return Err(format!("{} levels is over {}", self.levels, gpu::CAMERA_GRID_MAX_LEVELS));
        }
        if self.cells_per_level() * u64::from(self.levels) > u64::from(u32::MAX) {
            return Err(format!("{} cells × {} levels do not fit a 32-bit slot", self.dims, self.levels));
        }
        if !(self.cell.is_finite() && self.cell.min_element() > 0.0) {
            return Err(format!("a cell edge of {} m", self.cell));
        }
        Ok(())
    }

    /// Cells of one level.
    pub fn cells_per_level(&self) -> u64 {
        self.dims.as_u64vec3().element_product()
    }

    /// Bytes of every level: all the grid ever holds.
    pub fn bytes(&self) -> u64 {
        self.cells_per_level() * u64::from(self.levels) * u64::from(self.texel_bytes)
    }

    /// Edge of a cell of `level` per axis (m).
    pub fn cell_size(&self, level: u32) -> DVec3 {
        self.cell * f64::from(1u32 << level)
    }
}

/// A box of a window's local cells (`start + [0, size)` per axis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellBox {
    /// First local cell.
    pub start: UVec3,
    /// Extent per axis (0 on some axis: the box is empty).
    pub size: UVec3,
}

impl CellBox {
    /// Cells in the box.
    pub fn cells(&self) -> u64 {
        self.size.as_u64vec3().element_product()
    }
}

/// How a level's window moved, and the cells that entered it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scroll {
    /// The level.
    pub level: u32,
    /// The window's first cell now, on the level's world lattice.
    pub first: I64Vec3,
    /// The window's first cell's slot now (`first mod dims`).
    pub base: UVec3,
    /// The cells that entered: disjoint boxes of local cells of the new window.
    pub boxes: [CellBox; gpu::CAMERA_GRID_BOXES as usize],
}

impl Scroll {
    /// Cells that entered.
    pub fn cells(&self) -> u64 {
        self.boxes.iter().map(CellBox::cells).sum()
    }

    /// Call `fill` with every local cell that entered, box by box (x fastest, then y, then z,
    /// the order `camera_grid_entered` numbers them in).
    pub fn for_each_entered(&self, mut fill: impl FnMut(UVec3)) {
        for b in &self.boxes {
            for z in 0..b.size.z {
                for y in 0..b.size.y {
                    for x in 0..b.size.x {
                        fill(b.start + UVec3::new(x, y, z));
                    }
                }
            }
        }
    }

    /// The push constants of the fill dispatch of a grid of `dims` cells per level.
    pub fn push(&self, dims: UVec3) -> FillPush {
        let mut push = FillPush::zeroed();
        let mut before = 0u32;
        for (k, b) in self.boxes.iter().enumerate() {
            push.box_start[k] = b.start.extend(before);
            push.box_size[k] = b.size.extend(0);
            before += b.cells() as u32;
        }
        push.base = self.base.extend(self.level);
        push.dims = dims.extend(before);
        push
    }
}

/// The push constants of a fill dispatch (`CameraGridFill` in `shaders/common/camera_grid.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FillPush {
    /// Per box: xyz its first local cell, w the cells of the boxes before it.
    pub box_start: [UVec4; gpu::CAMERA_GRID_BOXES as usize],
    /// Per box: xyz its extent.
    pub box_size: [UVec4; gpu::CAMERA_GRID_BOXES as usize],
    /// xyz the window's toroidal base, w the level.
    pub base: UVec4,
    /// xyz cells per axis of a level, w the cells that entered.
    pub dims: UVec4,
}

/// The largest push-constant block every Vulkan device takes (`maxPushConstantsSize` ≥ 128).
const _: () = assert!(std::mem::size_of::<FillPush>() <= 128);

/// The slot of a window's local cell `local` (each axis below `dims`) whose first cell sits at
/// slot `base`: the toroidal wrap, then x fastest, then y, then z. `camera_grid_slot` in GLSL.
pub fn slot(local: UVec3, base: UVec3, dims: UVec3) -> u32 {
    let s = local + base;
    let s = s - UVec3::select(s.cmpge(dims), dims, UVec3::ZERO);
    (s.z * dims.y + s.y) * dims.x + s.x
}

/// The slot of world cell `world` in a level of `dims` cells per axis: `world mod dims`, however
/// far from the world's origin (the same slot [`slot`] gives for its local cell).
pub fn world_slot(world: I64Vec3, dims: UVec3) -> u32 {
    let s = world.rem_euclid(dims.as_i64vec3()).as_uvec3();
    (s.z * dims.y + s.y) * dims.x + s.x
}

/// A camera grid's windows: where each level lies on its world lattice, or that it holds nothing
/// yet. The cells themselves are the owner's buffer or image of [`GridShape::bytes`].
#[derive(Clone, Debug)]
pub struct CameraGrid {
    shape: GridShape,
    /// Per level, the first cell of the window the grid holds (`None`: not filled).
    windows: Vec<Option<I64Vec3>>,
}

impl CameraGrid {
    /// A grid of `shape` holding nothing: the first scroll of each level fills it whole.
    pub fn new(shape: GridShape) -> Result<Self, String> {
        shape.check()?;
        Ok(Self { shape, windows: vec![None; shape.levels as usize] })
    }

    /// The shape.
    pub fn shape(&self) -> &GridShape {
        &self.shape
    }

    /// Forget what the grid holds (it was not written, or its source changed): the next scroll
    /// of each level fills it whole.
    pub fn invalidate(&mut self) {
        self.windows.fill(None);
    }

    /// The window of `level` centred on `centre` (world, m): the cell under it and half the
    /// window before it on each axis (`dims / 2` cells).
    pub fn window_around(&self, level: u32, centre: DVec3) -> I64Vec3 {
        let under = (centre / self.shape.cell_size(level)).floor().as_i64vec3();
        under - (self.shape.dims / 2).as_i64vec3()
    }

    /// Move every level's window to centre on `centre`; the levels that moved (or were empty),
    /// with their cells to fill.
    pub fn follow(&mut self, centre: DVec3) -> Vec<Scroll> {
        (0..self.shape.levels).filter_map(|l| self.scroll_to(l, self.window_around(l, centre))).collect()
    }

    /// Move `level`'s window so its first cell is `first`: `None` if it already is, else the
    /// cells that entered (all of them for an empty level or a move of a window or more).
    pub fn scroll_to(&mut self, level: u32, first: I64Vec3) -> Option<Scroll> {
        let dims = self.shape.dims;
        let previous = self.windows[level as usize].replace(first);
        let whole = CellBox { start: UVec3::ZERO, size: dims };
        let empty = CellBox { start: UVec3::ZERO, size: UVec3::ZERO };
        let mut boxes = [empty; gpu::CAMERA_GRID_BOXES as usize];
        let moved = previous.map(|p| first - p);
        match moved {
            Some(d) if d == I64Vec3::ZERO => return None,
            Some(d) if (d.abs().cmplt(dims.as_i64vec3())).all() => {
                // Along each axis, the entered slab, over the cells the earlier axes kept.
                let mut kept = whole;
                for axis in 0..3 {
                    let (n, m) = (dims[axis], d[axis].unsigned_abs() as u32);
                    if m == 0 {
                        continue;
                    }
                    let (enter, keep) = if d[axis] > 0 { (n - m, 0) } else { (0, m) };
                    let mut slab = kept;
                    slab.start[axis] = enter;
                    slab.size[axis] = m;
                    boxes[axis] = slab;
                    kept.start[axis] = keep;
                    kept.size[axis] = n - m;
                }
            }
            _ => boxes[0] = whole,
        }
        let base = first.rem_euclid(dims.as_i64vec3()).as_uvec3();
        Some(Scroll { level, first, base, boxes })
    }

    /// The first cell of `level`'s window, if it holds one.
    pub fn window(&self, level: u32) -> Option<I64Vec3> {
        self.windows[level as usize]
    }

    /// The slot (counted over every level) that holds world cell `world` of `level`, if the
    /// level's window covers it.
    pub fn slot_of(&self, level: u32, world: I64Vec3) -> Option<u64> {
        let first = self.windows[level as usize]?;
        let local = world - first;
        let inside = local.cmpge(I64Vec3::ZERO).all() && local.cmplt(self.shape.dims.as_i64vec3()).all();
        inside.then(|| u64::from(level) * self.shape.cells_per_level() + u64::from(world_slot(world, self.shape.dims)))
    }

    /// The corner of `level`'s first cell relative to `origin` (world, m; the frame's O): the
    /// difference taken in f64, small enough for f32 near the camera.
    pub fn corner(&self, level: u32, first: I64Vec3, origin: DVec3) -> Vec3 {
        (first.as_dvec3() * self.shape.cell_size(level) - origin).as_vec3()
    }
}

/// Record the fill dispatch of `scroll`: `pipeline` (a shader that includes
/// `shaders/common/camera_grid.glsl` and reads `CameraGridFill` as its push constants at offset 0 of
/// `layout`, compute stage) over the cells that entered, `CAMERA_GRID_GROUP` a workgroup. The
/// caller binds the pipeline's sets and declares what it writes. `scroll` enters at least one
/// cell (`CameraGrid::scroll_to` returns none that enters nothing).
pub fn record_fill(
    device: &Device,
    cmd: vk::CommandBuffer,
    (layout, pipeline): (vk::PipelineLayout, vk::Pipeline),
    scroll: &Scroll,
    dims: UVec3,
) {
    let push = scroll.push(dims);
    let groups = push.dims.w.div_ceil(gpu::CAMERA_GRID_GROUP);
    // SAFETY: cmd is recording outside a rendering instance; the layout's compute push range
    // holds `FillPush` at offset 0.
    unsafe {
        device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
        device.raw.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, bytemuck::bytes_of(&push));
        device.raw.cmd_dispatch(cmd, groups, 1, 1);
    }
}

/// The push-constant range of a fill pipeline's layout.
pub fn push_constant_range() -> vk::PushConstantRange {
    vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::COMPUTE,
        offset: 0,
        size: std::mem::size_of::<FillPush>() as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(dims: UVec3, levels: u32) -> CameraGrid {
        CameraGrid::new(GridShape { dims, cell: DVec3::new(0.5, 0.25, 2.0), levels, texel_bytes: 4 }).expect("shape")
    }

    /// The world cell each slot holds after `moves`, kept as a fill would keep it: the entered
    /// cells written with their world cell, the others left as they were.
    fn replay(grid: &mut CameraGrid, level: u32, moves: &[I64Vec3]) -> Vec<Option<I64Vec3>> {
        let mut slots = vec![None; grid.shape().cells_per_level() as usize];
        let dims = grid.shape().dims;
        for &first in moves {
            if let Some(scroll) = grid.scroll_to(level, first) {
                scroll.for_each_entered(|local| {
                    let s = slot(local, scroll.base, dims) as usize;
                    slots[s] = Some(first + local.as_i64vec3());
                });
            }
        }
        slots
    }

    #[test]
    fn every_slot_holds_the_world_cell_its_address_names_after_any_moves() {
        // 2-D and 3-D, odd and even sizes, moves of 0, 1, a few, all but one and more than a
        // window's cells on each axis and diagonally, near the origin and 100 km from it.
        for dims in [UVec3::new(7, 1, 5), UVec3::new(4, 3, 6), UVec3::new(161, 1, 161)] {
            let far = I64Vec3::new(200_000, 0, -400_000);
            for start in [I64Vec3::ZERO, far, -far] {
                let mut g = grid(dims, 1);
                let d = dims.as_i64vec3();
                let steps = [
                    I64Vec3::ZERO,
                    I64Vec3::X,
                    I64Vec3::new(-3, 0, 2),
                    d - 1,
                    I64Vec3::new(0, 0, -1),
                    I64Vec3::new(1 - d.x, 1 - d.y, 0),
                    d,
                    I64Vec3::new(-2 * d.x - 1, 0, 5),
                    I64Vec3::new(2, 1, 1),
                ];
                let mut first = start;
                let moves: Vec<I64Vec3> = steps
                    .iter()
                    .map(|s| {
                        first += *s;
                        first
                    })
                    .collect();
                let slots = replay(&mut g, 0, &moves);
                let mut seen = 0;
                for z in 0..d.z {
                    for y in 0..d.y {
                        for x in 0..d.x {
                            let world = first + I64Vec3::new(x, y, z);
                            let s = g.slot_of(0, world).expect("inside the window") as usize;
                            assert_eq!(slots[s], Some(world), "{dims}: slot {s}");
                            assert_eq!(s, world_slot(world, dims) as usize);
                            seen += 1;
                        }
                    }
                }
                assert_eq!(seen, g.shape().cells_per_level());
                assert_eq!(g.slot_of(0, first - I64Vec3::X), None);
                assert_eq!(g.slot_of(0, first + d), None);
            }
        }
    }

    #[test]
    fn a_scroll_enters_exactly_the_cells_that_were_not_in_the_window() {
        let dims = UVec3::new(6, 3, 5);
        let mut g = grid(dims, 1);
        let first = I64Vec3::new(-10, 4, 100);
        assert_eq!(g.scroll_to(0, first).expect("empty grid").cells(), 90, "an empty grid fills whole");
        assert_eq!(g.scroll_to(0, first), None, "no move, nothing to fill");
        for d in [I64Vec3::new(1, 0, 0), I64Vec3::new(-2, 1, 3), I64Vec3::new(5, -2, -4), I64Vec3::new(0, 0, -5)] {
            let old = g.window(0).expect("filled");
            let scroll = g.scroll_to(0, old + d).expect("moved");
            let mut entered = std::collections::HashSet::new();
            scroll.for_each_entered(|local| assert!(entered.insert(local), "{local} entered twice"));
            for z in 0..dims.z {
                for y in 0..dims.y {
                    for x in 0..dims.x {
                        let local = UVec3::new(x, y, z);
                        let was = old + d + local.as_i64vec3() - old;
                        let inside_before = was.cmpge(I64Vec3::ZERO).all() && was.cmplt(dims.as_i64vec3()).all();
                        assert_eq!(entered.contains(&local), !inside_before, "move {d}, cell {local}");
                    }
                }
            }
            assert_eq!(scroll.cells(), entered.len() as u64);
        }
    }

    #[test]
    fn the_push_constants_number_the_boxes_as_the_shader_reads_them() {
        let dims = UVec3::new(8, 1, 8);
        let mut g = grid(dims, 2);
        g.scroll_to(1, I64Vec3::ZERO);
        let scroll = g.scroll_to(1, I64Vec3::new(2, 0, -3)).expect("moved");
        let push = scroll.push(dims);
        assert_eq!(push.base, UVec4::new(2, 0, 5, 1));
        assert_eq!(push.dims, UVec4::new(8, 1, 8, 2 * 8 + 6 * 3));
        // Box k starts at the cells of the boxes before it; invocation i maps as the GLSL does.
        let mut cells = Vec::new();
        scroll.for_each_entered(|c| cells.push(c));
        for (i, &cell) in cells.iter().enumerate() {
            let i = i as u32;
            let k = (1..3).filter(|&k| i >= push.box_start[k].w).count();
            let (start, size) = (push.box_start[k].truncate(), push.box_size[k].truncate());
            let j = i - push.box_start[k].w;
            let local = start + UVec3::new(j % size.x, (j / size.x) % size.y, j / (size.x * size.y));
            assert_eq!(local, cell, "invocation {i}");
        }
    }

    #[test]
    fn nested_levels_centre_on_the_camera_each_on_its_own_lattice() {
        let shape =
            GridShape { dims: UVec3::new(16, 1, 16), cell: DVec3::new(1.0, 1.0, 1.0), levels: 3, texel_bytes: 16 };
        let mut g = CameraGrid::new(shape).expect("shape");
        assert_eq!(shape.bytes(), 3 * 256 * 16);
        let camera = DVec3::new(100_000.3, 0.0, -7.9);
        let scrolls = g.follow(camera);
        assert_eq!(scrolls.len(), 3);
        for l in 0..3 {
            let first = g.window(l).expect("filled");
            let edge = shape.cell_size(l);
            // The camera's cell is the window's middle one; level l spans 2^l times level 0.
            let under = (camera / edge).floor().as_i64vec3();
            assert_eq!(under - first, I64Vec3::new(8, 0, 8));
            let corner = g.corner(l, first, DVec3::new(100_000.0, 0.0, 0.0));
            assert_eq!(corner.x, (first.x as f64 * edge.x - 100_000.0) as f32);
            assert!(corner.x < 0.3 && corner.x + 16.0 * edge.x as f32 > 0.3);
        }
        // Moving within level 2's cell moves the finer levels only.
        let moved = g.follow(camera + DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(moved.iter().map(|s| s.level).collect::<Vec<_>>(), [0]);
        // Slots are counted over the levels.
        let w = g.window(2).expect("filled");
        assert!(g.slot_of(2, w).expect("inside") >= 2 * 256);
    }

    #[test]
    fn shapes_the_addressing_cannot_hold_are_refused() {
        let ok = GridShape { dims: UVec3::new(4, 1, 4), cell: DVec3::ONE, levels: 1, texel_bytes: 4 };
        assert!(ok.check().is_ok());
        assert!(GridShape { dims: UVec3::new(4, 0, 4), ..ok }.check().is_err());
        assert!(GridShape { levels: 0, ..ok }.check().is_err());
        assert!(GridShape { levels: gpu::CAMERA_GRID_MAX_LEVELS + 1, ..ok }.check().is_err());
        assert!(GridShape { cell: DVec3::new(1.0, f64::NAN, 1.0), ..ok }.check().is_err());
        assert!(GridShape { cell: DVec3::new(1.0, 0.0, 1.0), ..ok }.check().is_err());
        assert!(GridShape { dims: UVec3::splat(2048), ..ok }.check().is_err());
    }
}
