//! A block field's ground as a clipmap (issue #30 item 2): nested levels of one camera grid
//! (`render::camera_grid`), level l a window of `CELLS`² cells of 2^l times level 0's step on the
//! world's lattice of that step, so the ground is drawn in fine cells under the camera at any view
//! distance and in coarse ones far out. Each texel holds what depends on its world vertex alone:
//! the relief's height there, the height of the next level's mesh there (an odd vertex's mean of
//! the two even vertices it halves) and the relief's normal (`shaders/terrain/relief_fill.comp`).
//!
//! - **Windows.** Level 0's window is centred on O's cell, snapped to `SNAP` of its cells; level
//!   l's is centred on level l − 1's, snapped to `SNAP` of its own. So each level's window holds
//!   the finer one's at an offset of 16 or 24 of its cells, a whole number of terrain chunks
//!   (`render::terrain_chunks::GROUND_CHUNK_CELLS`): the terrain pass draws a level's chunks but those
//!   of the hole the finer level fills ([`Clipmap::hole`]). A window moves only when O has moved
//!   by `SNAP / 2` cells of its level, and then only the cells that entered are filled. The
//!   windows are placed in the world's period that holds O ([`period_cell`]), so a view a period
//!   away draws what this one draws.
//! - **World-exact texels.** A texel is a function of its world vertex alone, not of O: the
//!   relief's phases are taken on the world's period in whole half-metres, (m X + n Z) mod
//!   `PERIOD_HALF_METRES`, in integers (`relief_fill.comp`). So the texels that stay when a
//!   window moves are those a fresh fill writes, and a level's even vertex is bit for bit the
//!   next level's vertex at the same place.
//! - **Morph.** A level's odd vertices slide onto the next level's mesh over the `MORPH_END`
//!   cells next to its window's edge ([`morph`], CDLOD's morph keyed by the vertex's place in the
//!   window), fully within `MORPH_FULL` of it. At the edge a level is the next level's mesh, so
//!   the two meet without cracks, and roots, which read the level that draws them, sit on the
//!   drawn ground.

use glam::{DVec2, DVec3, I64Vec2, I64Vec3, IVec2, IVec4, UVec2, UVec3, Vec4};

use crate::render::camera_grid::GridShape;
use crate::render::gpu_constants as gpu;
use crate::scene::field::{self, BLOCK_SIZE};

/// Cells per side of a level's window.
pub const CELLS: u32 = gpu::FIELD_TERRAIN_CELLS;
/// A window moves by whole multiples of this many of its level's cells.
pub const SNAP: u32 = gpu::GROUND_SNAP_CELLS;
/// A level's odd vertices lie on the next level's mesh within this many cells of its window's edge.
pub const MORPH_FULL: u32 = gpu::GROUND_MORPH_FULL;
/// ... and start to slide onto it at this many.
pub const MORPH_END: u32 = gpu::GROUND_MORPH_END;
/// The world's period in half-metres: the lattice the texels' phases are taken on.
pub const PERIOD_HALF_METRES: i64 = 2 * field::WORLD_PERIOD as i64;

const _: () =
    assert!(CELLS.is_multiple_of(SNAP) && (SNAP / 2).is_multiple_of(crate::render::terrain_chunks::GROUND_CHUNK_CELLS));
const _: () = assert!(MORPH_FULL < MORPH_END && MORPH_END < SNAP);

/// A block field's clipmap: level 0's cell edge and the levels the view distance needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clipmap {
    /// Level 0's cell edge (m): a power of two times the block's, at least 1 m.
    pub step: f32,
    /// Levels held, at most `CAMERA_GRID_MAX_LEVELS`.
    pub levels: u32,
}

impl Clipmap {
    /// The clipmap for the ground out to `view_distance` with blades out to `blade_range`: level
    /// 0 in the cells of `terrain_step` for the nearer of the two, as many levels as reach the view distance (`reach`), and a
    /// coarser level 0 when `CAMERA_GRID_MAX_LEVELS` would not.
    pub fn for_view(view_distance: f32, blade_range: f32) -> Self {
        let mut step = terrain_step(view_distance.min(blade_range));
        loop {
            let levels = (1..=gpu::CAMERA_GRID_MAX_LEVELS).find(|&l| Self { step, levels: l }.reach() >= view_distance);
            match levels {
                Some(levels) => return Self { step, levels },
                None => step *= 2.0,
            }
        }
    }

    /// Cell edge of `level` (m).
    pub fn step(&self, level: u32) -> f32 {
        self.step * (1u32 << level) as f32
    }

    /// How far from the camera, in x and z, the coarsest level holds the ground wherever the
    /// camera stands in O's cell: its half window, less how far its centre can lie from the
    /// camera (level 0's snap, half a block, and each level's 8 cells from the finer one's
    /// centre: 16 of its own cells and 2 m in all).
    pub fn reach(&self) -> f32 {
        let top = self.step(self.levels - 1);
        (CELLS / 2 - SNAP / 2) as f32 * top - 0.5 * BLOCK_SIZE
    }

    /// The levels as one camera grid: (`CELLS` + 1)² vertices a level, 16 bytes each.
    pub fn shape(&self) -> GridShape {
        let n = CELLS + 1;
        let step = f64::from(self.step);
        GridShape { dims: UVec3::new(n, 1, n), cell: DVec3::new(step, 1.0, step), levels: self.levels, texel_bytes: 16 }
    }

    /// Each level's window for O's cell `cell`: its first vertex on the level's world lattice,
    /// in the world's period that holds O (`period_cell`; see the module's comment).
    pub fn windows(&self, cell: IVec2) -> Vec<I64Vec2> {
        let snap = i64::from(SNAP);
        let half = i64::from(CELLS / 2);
        let cell = period_cell(cell);
        let centre = (cell.as_dvec2() + DVec2::splat(0.5)) * f64::from(BLOCK_SIZE) / f64::from(self.step);
        let first = ((centre - DVec2::splat(half as f64)) / snap as f64 + DVec2::splat(0.5)).floor();
        let mut windows = vec![first.as_i64vec2() * snap];
        for _ in 1..self.levels {
            let finer = *windows.last().expect("level 0");
            // Level l - 1's centre in level l's cells (its first vertex is even: a multiple of SNAP).
            let centre = finer / 2 + I64Vec2::splat(half / 2);
            let start = (centre - I64Vec2::splat(half)).as_dvec2() / snap as f64 + DVec2::splat(0.5);
            windows.push(start.floor().as_i64vec2() * snap);
        }
        windows
    }

    /// The cells of `level`'s window that the finer level draws (its hole): their first cell,
    /// local to the window (`SNAP` or `3 SNAP / 2` per axis); they span `CELLS / 2` per side.
    /// `None` for level 0.
    pub fn hole(windows: &[I64Vec2], level: u32) -> Option<UVec2> {
        let l = level as usize;
        (l > 0).then(|| (windows[l - 1] / 2 - windows[l]).as_uvec2())
    }

    /// The frame's clipmap uniforms for O's cell `cell`: per level the
    /// window's first vertex relative to O and the cell edge (`ground_levels`), and the window's
    /// toroidal base and first vertex in half-metres on the world's period (`ground_windows`).
    pub fn uniforms(&self, cell: IVec2) -> ([Vec4; 8], [IVec4; 8]) {
        let (mut levels, mut windows) = ([Vec4::ZERO; 8], [IVec4::ZERO; 8]);
        let origin = period_cell(cell).as_dvec2() * f64::from(BLOCK_SIZE);
        let dims = self.shape().dims.as_i64vec3();
        for (l, first) in self.windows(cell).into_iter().enumerate() {
            let step = self.step(l as u32);
            let offset = (first.as_dvec2() * f64::from(step) - origin).as_vec2();
            levels[l] = Vec4::new(offset.x, offset.y, step, 0.0);
            let base = I64Vec3::new(first.x, 0, first.y).rem_euclid(dims);
            let half_metres = (first * (2.0 * step) as i64).rem_euclid(I64Vec2::splat(PERIOD_HALF_METRES));
            windows[l] = IVec4::new(base.x as i32, base.z as i32, half_metres.x as i32, half_metres.y as i32);
        }
        (levels, windows)
    }
}

/// Edge of level 0's cells for ground out to `distance`: 1 m when that one level in 1 m cells
/// reaches it, else 2 m (the cells the single grid the clipmap replaced had at the default 150 m;
/// the relief's shortest wave is 6 m long). A power of two times the block edge, so the lattice
/// stays put when O moves by a block.
pub fn terrain_step(distance: f32) -> f32 {
    if (Clipmap { step: 1.0, levels: 1 }).reach() >= distance {
        1.0
    } else {
        2.0
    }
}

impl Clipmap {
    /// Where world point `p` (x, z) lies for `windows` (`Clipmap::windows`): the finest level
    /// whose window holds it (its edge included) and its place there in that level's cells; past
    /// the coarsest window, the coarsest. `ground_level_at` of `shaders/common/ground.glsl`.
    pub fn level_at(&self, windows: &[I64Vec2], p: DVec2) -> (u32, DVec2) {
        let at = |l: u32| (p / f64::from(self.step(l)) - windows[l as usize].as_dvec2(), l);
        let n = f64::from(CELLS);
        let (g, level) = (0..self.levels - 1)
            .map(at)
            .find(|(g, _)| g.min_element() >= 0.0 && g.max_element() <= n)
            .unwrap_or_else(|| at(self.levels - 1));
        (level, g)
    }

    /// The edge of the drawn cells under a block cell whose centre is world `centre`: its level's
    /// step, or two where that level's vertices may slide onto the next level's mesh (`morph`).
    /// `cell_spread` of it bounds the cell's roots. Mirrors `field_cell_bounds` in
    /// `shaders/common/field.glsl`.
    pub fn drawn_step(&self, windows: &[I64Vec2], centre: DVec2) -> f32 {
        let (level, g) = self.level_at(windows, centre);
        let step = self.step(level);
        let edge = g.min_element().min(f64::from(CELLS) - g.max_element()) as f32;
        // The cell's half edge, the cell of vertices around it and their coarse neighbours.
        let reach = 0.5 * BLOCK_SIZE / step + 2.0;
        if edge - reach < MORPH_END as f32 {
            2.0 * step
        } else {
            step
        }
    }

    /// The drawn ground's height at world `p` (near O) for O's cell `cell`, from the relief itself (f64):
    /// the heights `relief_fill.comp` gives the vertices of the cell under `p` in the level that
    /// draws it, morphed as `ground_vertex` morphs them, split as terrain.vert splits the cell.
    /// The CPU mirror of the drawn surface.
    pub fn drawn_height(&self, relief: &field::Relief, cell: IVec2, p: DVec2) -> f64 {
        self.drawn_height_of(&|at| relief_at_half_metres(relief, at), cell, p)
    }

    /// `drawn_height` of any ground given by its height at a world vertex in half-metres on the
    /// world's period (`relief_at_half_metres`; a heightmap's, `heightmap_fill.comp`'s).
    pub fn drawn_height_of(&self, ground: &dyn Fn(I64Vec2) -> f64, cell: IVec2, p: DVec2) -> f64 {
        let windows = self.windows(cell);
        let p = p - (cell - period_cell(cell)).as_dvec2() * f64::from(BLOCK_SIZE);
        let (level, g) = self.level_at(&windows, p);
        let step_hm = (2.0 * self.step(level)) as i64;
        let first = windows[level as usize];
        let vertex = |v: IVec2| {
            let v = v.clamp(IVec2::ZERO, IVec2::splat(CELLS as i32));
            let at =
                |v: IVec2| ground(((first + v.as_i64vec2()) * step_hm).rem_euclid(I64Vec2::splat(PERIOD_HALF_METRES)));
            let odd = IVec2::new(v.x & 1, v.y & 1);
            let h = at(v);
            let k = f64::from(self.morph(level, v.as_uvec2()));
            if odd == IVec2::ZERO || k == 0.0 {
                return h;
            }
            h + k * (0.5 * (at(v - odd) + at(v + odd)) - h)
        };
        let c = g.floor().clamp(DVec2::ZERO, DVec2::splat(f64::from(CELLS - 1)));
        let f = (g - c).clamp(DVec2::ZERO, DVec2::ONE);
        let c = c.as_ivec2();
        let (h00, h10) = (vertex(c), vertex(c + IVec2::X));
        let (h01, h11) = (vertex(c + IVec2::Y), vertex(c + IVec2::ONE));
        if f.x >= f.y {
            h00 + f.x * (h10 - h00) + f.y * (h11 - h10)
        } else {
            h00 + f.y * (h01 - h00) + f.x * (h11 - h01)
        }
    }

    /// How far local vertex `v` of `level` has slid onto the next level's mesh ([`morph`]); the
    /// coarsest level has no next and keeps the relief.
    pub fn morph(&self, level: u32, v: UVec2) -> f32 {
        if level + 1 < self.levels {
            morph(v)
        } else {
            0.0
        }
    }
}

/// How far the drawn terrain over a block cell can rise or fall from the relief at the cell's
/// centre, for drawn cells of `step` metres (`Clipmap::drawn_step`) and a relief whose slope is at most `slope_bound`
/// (`shaders/common/field.glsl`, `field_cell_bounds`, computes the same). The terrain interpolates the
/// relief at the grid's vertices: with cells of at most half a block they lie in the block's
/// square, within 0.7071 of its edge from the centre; coarser cells reach √2 (step − edge / 2)
/// further.
pub fn cell_spread(slope_bound: f32, step: f32) -> f32 {
    slope_bound * (CELL_SPREAD_INSIDE * BLOCK_SIZE + CELL_SPREAD_OUTSIDE * (step - 0.5 * BLOCK_SIZE).max(0.0))
}

/// `cell_spread`'s reach per metre of block edge inside the block's square: √½, rounded up
/// (mirrored in `shaders/common/field.glsl`, checked by `tests/shader_sources.rs`).
pub const CELL_SPREAD_INSIDE: f32 = 0.7072;
/// `cell_spread`'s further reach per metre of a coarse terrain cell past half a block: √2,
/// rounded up (mirrored in `shaders/common/field.glsl`).
pub const CELL_SPREAD_OUTSIDE: f32 = 1.4143;

/// O's cell `cell` in the world's first period (cells 0 .. `PERIOD_CELLS`): the windows are
/// placed there, so a view a period away draws the same levels (a coarse level's snap does not
/// divide the period). When O crosses into the next period the levels' places jump, and the
/// clipmap is filled anew.
pub fn period_cell(cell: IVec2) -> IVec2 {
    cell.rem_euclid(IVec2::splat(field::PERIOD_CELLS))
}

/// The camera grid's window of a level whose first vertex is `first` (x, z; y 0).
pub fn grid_window(first: I64Vec2) -> I64Vec3 {
    I64Vec3::new(first.x, 0, first.y)
}

/// How far local vertex `v` of a level's window has slid from the relief onto the next level's
/// mesh: 1 within `MORPH_FULL` cells of the window's edge (Chebyshev), 0 from `MORPH_END` on,
/// linear between. Mirrors `ground_vertex_height` in `shaders/common/ground.glsl`.
pub fn morph(v: UVec2) -> f32 {
    let edge = v.x.min(v.y).min(CELLS - v.x).min(CELLS - v.y);
    let band = (MORPH_END - MORPH_FULL) as f32;
    ((MORPH_END as f32 - edge as f32) / band).clamp(0.0, 1.0)
}

/// The drawn height at local vertex `v` of `level` from its texel (the relief's height, the next
/// level's mesh's height, the slope along x and z): `ground_vertex_height` of
/// `shaders/common/ground.glsl` on the CPU.
pub fn drawn_texel_height(clipmap: &Clipmap, level: u32, texel: [f32; 4], v: UVec2) -> f32 {
    let k = clipmap.morph(level, v);
    if (v.x | v.y) & 1 != 0 && k > 0.0 {
        texel[0] * (1.0 - k) + texel[1] * k
    } else {
        texel[0]
    }
}

/// The relief at a world vertex given in half-metres on the world's period, as
/// `relief_fill.comp` evaluates it (in f64): Σ a_k sin(2π ((m_k X + n_k Z) mod P) / P + φ_k).
pub fn relief_at_half_metres(relief: &field::Relief, at: I64Vec2) -> f64 {
    let at = at.rem_euclid(I64Vec2::splat(PERIOD_HALF_METRES));
    let world = at.as_dvec2() * 0.5;
    relief.height(world.x, world.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_level_holds_the_finer_one_on_whole_chunks() {
        for (view, blades) in [(150.0, 150.0), (5000.0, 150.0), (10_000.0, 504.0), (40.0, 40.0)] {
            let clipmap = Clipmap::for_view(view, blades);
            assert!(clipmap.reach() >= view && clipmap.levels <= gpu::CAMERA_GRID_MAX_LEVELS, "{clipmap:?}");
            for cell in [IVec2::ZERO, IVec2::new(-1, 7), IVec2::new(25_003, -12_345), IVec2::new(15, 16)] {
                let windows = clipmap.windows(cell);
                assert!(windows.iter().all(|w| w.x % i64::from(SNAP) == 0 && w.y % i64::from(SNAP) == 0));
                for l in 1..clipmap.levels {
                    let hole = Clipmap::hole(&windows, l).expect("a hole");
                    for axis in [hole.x, hole.y] {
                        assert!(axis == SNAP || axis == 3 * SNAP / 2, "{clipmap:?} {cell}: level {l}'s hole at {hole}");
                    }
                }
                // The camera anywhere in O's cell is `reach` inside the coarsest window.
                let top = clipmap.levels - 1;
                let step = f64::from(clipmap.step(top));
                let lo = windows[top as usize].as_dvec2() * step;
                let hi = lo + DVec2::splat(f64::from(CELLS) * step);
                // The windows lie in the world's period that holds O (`period_cell`).
                let corner = period_cell(cell).as_dvec2() * f64::from(BLOCK_SIZE);
                for camera in [corner, corner + DVec2::splat(f64::from(BLOCK_SIZE))] {
                    let inside = (camera - lo).min(hi - camera).min_element();
                    assert!(inside >= f64::from(clipmap.reach()) - 1e-9, "{clipmap:?} {cell}: {inside}");
                }
            }
        }
    }

    #[test]
    fn the_morph_is_whole_at_the_edge_and_nothing_inside() {
        assert_eq!(morph(UVec2::new(0, CELLS / 2)), 1.0);
        assert_eq!(morph(UVec2::new(CELLS / 2, CELLS - MORPH_FULL)), 1.0);
        assert_eq!(morph(UVec2::new(CELLS / 2, CELLS / 2)), 0.0);
        assert_eq!(morph(UVec2::new(MORPH_END, CELLS / 2)), 0.0);
        let mid = morph(UVec2::new((MORPH_FULL + MORPH_END) / 2, CELLS / 2));
        assert!(mid > 0.0 && mid < 1.0);
    }

    #[test]
    fn a_cells_drawn_ground_stays_within_its_spread_at_every_level() {
        // The cull's cell and root boxes (field.glsl) bound the roots by the relief at the cell's
        // centre ± `cell_spread` of the drawn cells' edge: the roots sit on the drawn ground,
        // which in levels of wide cells interpolates vertices outside the cell.
        let relief = field::Relief::generate(1);
        let slope = relief.slope_bound();
        let clipmap = Clipmap::for_view(5000.0, 150.0);
        let (mut widest, mut levels) = (0.0f64, std::collections::BTreeSet::new());
        for o in [IVec2::ZERO, IVec2::new(1, -2), IVec2::new(25_003, 9)] {
            let windows = clipmap.windows(o);
            for k in 0..600 {
                // Cells along a spiral out to 1.5 km, across every level boundary.
                let (angle, radius) = (f64::from(k) * 0.61, f64::from(k) * 2.5);
                let c = (DVec2::new(angle.cos(), angle.sin()) * radius / f64::from(BLOCK_SIZE)).floor();
                let corner = (o.as_dvec2() + c) * f64::from(BLOCK_SIZE);
                let centre = corner + DVec2::splat(0.5 * f64::from(BLOCK_SIZE));
                let spread = f64::from(cell_spread(slope, clipmap.drawn_step(&windows, centre)));
                levels.insert(clipmap.level_at(&windows, centre).0);
                let mid = relief.height(centre.x, centre.y);
                // The cull's reference: the drawn ground at the centre, within twice the spread.
                let drawn_mid = clipmap.drawn_height(&relief, o, centre);
                for i in 0..=8 {
                    for j in 0..=8 {
                        let p = corner + DVec2::new(f64::from(i), f64::from(j)) * f64::from(BLOCK_SIZE) / 8.0;
                        let drawn = clipmap.drawn_height(&relief, o, p);
                        let off = (drawn - mid).abs();
                        assert!(off <= spread, "{p}: {off} past the spread {spread}");
                        assert!((drawn - drawn_mid).abs() <= 2.0 * spread, "{p}: past twice the spread {spread}");
                        widest = widest.max(off / spread);
                    }
                }
            }
        }
        assert!(levels.len() >= 5, "the spiral crossed levels {levels:?}");
        assert!(widest > 0.3, "the bound is never approached ({widest}): the test would mean little");
    }
}
