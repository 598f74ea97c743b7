//! A block field on the GPU (`scene::field`, Belyaev §2.1): the origin O each frame (the corner of
//! the block cell under the camera), the cameras relative to it, the grid of force corners that
//! follows it, and the field's part of the frame's uniforms. Everything the GPU sees is relative
//! to O, so a field 100 km from the world's origin renders as one at the origin does.

use glam::{DVec2, DVec3, I64Vec2, I64Vec3, IVec2, IVec4, UVec3, UVec4, Vec2, Vec3, Vec4};

use crate::render::camera_grid::GridShape;
use crate::render::gpu_constants as gpu;
use crate::render::uniforms::FrameUniforms;
use crate::scene::clusters::ClusterGrid;
use crate::scene::field::{self, BLOCK_SIZE};
use crate::scene::{Camera, Field};

// The shaders' world period (`cell_hash` in `shaders/common/field.glsl`) is the scene's.
const _: () = assert!(field::PERIOD_CELLS as u32 == gpu::PERIOD_CELLS);

/// `--field SIZE|infinite`, parsed: a side in metres, or `None` for an unbounded field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSize(pub Option<f32>);

/// Where this frame's positions are relative to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Origin {
    /// World (x, z) of O, exact in f64.
    pub world: DVec2,
    /// O's integer cell.
    pub cell: IVec2,
}

impl Origin {
    /// The corner of the cell under `camera`.
    pub fn under(camera: &Camera) -> Self {
        let (x, z) = field::cell_of(f64::from(camera.position.x), f64::from(camera.position.z));
        let cell = IVec2::new(x as i32, z as i32);
        Self { world: cell.as_dvec2() * f64::from(BLOCK_SIZE), cell }
    }

    /// `camera` relative to O (the difference taken in f64: small and exact enough).
    pub fn relative(&self, camera: &Camera) -> Camera {
        let p = camera.position;
        let x = (f64::from(p.x) - self.world.x) as f32;
        let z = (f64::from(p.z) - self.world.y) as f32;
        Camera { position: Vec3::new(x, p.y, z), ..*camera }
    }
}

/// Rings of cells around O's cell the cull visits for blades out to `blade_range` (one more than
/// the distance spans: the camera may stand anywhere in its cell).
pub fn ring_radius(blade_range: f32) -> u32 {
    (blade_range / BLOCK_SIZE).ceil() as u32 + 1
}

/// Ring slots (cells) the cull visits for `blade_range`: (2R + 1)².
pub fn ring_slots(blade_range: f32) -> u32 {
    let r = ring_radius(blade_range);
    (2 * r + 1) * (2 * r + 1)
}

/// The longest blade range the rings' slots can hold (the visible list packs a slot in 16 bits):
/// `--blade-distance`, not the view distance, which sizes the ground only.
pub fn max_blade_distance() -> f32 {
    // (2R + 1)² <= 65 536 for R <= 127.
    126.0 * BLOCK_SIZE
}

/// Edge of the terrain grid's cells for `view_distance`: a power of two times the block edge (so
/// the lattice stays put when O moves by a block), the smallest whose `FIELD_TERRAIN_CELLS` cells
/// span the view distance on both sides.
pub fn terrain_step(view_distance: f32) -> f32 {
    let span = 2.0 * (view_distance + BLOCK_SIZE);
    let cells = gpu::FIELD_TERRAIN_CELLS as f32;
    let mut step = BLOCK_SIZE;
    // At least 1 m: the relief's shortest wave is 6 m long.
    while step > 1.0 && cells * 0.5 * step >= span {
        step *= 0.5;
    }
    while cells * step < span {
        step *= 2.0;
    }
    step
}

/// The terrain grid's vertex 0 on the world's lattice of `step`-metre cells (its index: world
/// position / step), for O's cell `cell`: about half the grid before O's cell, so the vertices
/// stay put in the world when O moves by a block whatever the step (8 m cells, past 316 m of view
/// distance, would otherwise move by 4 m at every other block). The grid is a camera grid
/// (`relief_grid_shape`) whose window starts here.
pub fn terrain_grid_first(cell: IVec2, step: f32) -> I64Vec2 {
    let base = 0.5 * f64::from(BLOCK_SIZE) - 0.5 * f64::from(gpu::FIELD_TERRAIN_CELLS) * f64::from(step);
    let axis = |c: i32| ((f64::from(c) * f64::from(BLOCK_SIZE) + base) / f64::from(step)).ceil() as i64;
    I64Vec2::new(axis(cell.x), axis(cell.y))
}

/// Where the terrain grid's vertex 0 (`terrain_grid_first`) lies relative to O (O's cell
/// `cell`), per axis. `shaders/common/field.glsl` reads it as `terrain_grid_offset`.
pub fn terrain_grid_offset(cell: IVec2, step: f32) -> Vec2 {
    let first = terrain_grid_first(cell, step).as_dvec2() * f64::from(step);
    (first - cell.as_dvec2() * f64::from(BLOCK_SIZE)).as_vec2()
}

/// The terrain grid as a camera grid: one level of (`FIELD_TERRAIN_CELLS` + 1)² vertices, x and
/// z, on the lattice of `step`, a texel of 16 bytes each (the relief's height, the coarse mesh's
/// height, the normal's x and z: `shaders/terrain/relief_grid.comp`).
pub fn relief_grid_shape(step: f32) -> GridShape {
    let n = gpu::FIELD_TERRAIN_CELLS + 1;
    let step = f64::from(step);
    GridShape { dims: UVec3::new(n, 1, n), cell: DVec3::new(step, 1.0, step), levels: 1, texel_bytes: 16 }
}

/// The terrain grid's window for O's cell `cell`: its first vertex, x and z (y 0).
pub fn relief_grid_window(cell: IVec2, step: f32) -> I64Vec3 {
    let first = terrain_grid_first(cell, step);
    I64Vec3::new(first.x, 0, first.y)
}

/// How far the drawn terrain over a block cell can rise or fall from the relief at the cell's
/// centre, for terrain cells of `step` metres and a relief whose slope is at most `slope_bound`
/// (`shaders/common/field.glsl`, `field_cell_bounds`, computes the same). The terrain interpolates the
/// relief at the grid's vertices: with cells of at most half a block they lie in the block's
/// square, within 0.7071 of its edge from the centre; coarser cells reach √2 (step − edge / 2)
/// further.
pub fn cell_spread(slope_bound: f32, step: f32) -> f32 {
    slope_bound * (CELL_SPREAD_INSIDE * BLOCK_SIZE + CELL_SPREAD_OUTSIDE * (step - 0.5 * BLOCK_SIZE).max(0.0))
}

/// Whether a block field's far terrain is drawn in cells of two grid steps
/// (`render::terrain_chunks`): only when a block spans an even number of cells, so the coarse
/// lattice (the grid's even vertices) stays put in the world as O moves by blocks. Mirrored in
/// `shaders/common/field.glsl`.
pub fn terrain_coarsens(step: f32) -> bool {
    2.0 * step <= BLOCK_SIZE
}

/// How far grid vertex `v`'s height has slid from the relief onto the coarse mesh (an odd
/// vertex's coarse height is the mean of the two even vertices of the coarse edge or diagonal it
/// halves): 0 within `TERRAIN_MORPH_CELLS` of the grid's centre (Chebyshev), 1 from
/// `TERRAIN_FINE_CELLS` on, where the coarse chunks begin, linear between (CDLOD's morph, by the
/// grid's place rather than the camera's). The grid stores both heights, a function of the
/// world vertex alone, and its readers apply this (`relief_vertex`, `shaders/common/field.glsl`).
pub fn terrain_morph(v: glam::UVec2) -> f32 {
    let centre = (gpu::FIELD_TERRAIN_CELLS / 2) as i32;
    let d = (v.x as i32 - centre).abs().max((v.y as i32 - centre).abs());
    let band = (gpu::TERRAIN_FINE_CELLS - gpu::TERRAIN_MORPH_CELLS) as f32;
    ((d - gpu::TERRAIN_MORPH_CELLS as i32) as f32 / band).clamp(0.0, 1.0)
}

/// The drawn terrain's height at grid vertex `v` (`relief_vertex` of `shaders/common/field.glsl`
/// on the CPU): the relief there, an odd vertex slid by `terrain_morph` onto the mean of the two
/// even vertices of the coarse edge or diagonal it halves. `origin` is O in the world, `offset` the
/// grid's `terrain_grid_offset`.
pub fn drawn_vertex_height(relief: &field::Relief, origin: DVec2, offset: Vec2, step: f32, v: IVec2) -> f64 {
    let at = |v: IVec2| {
        let w = origin + offset.as_dvec2() + v.as_dvec2() * f64::from(step);
        relief.height(w.x, w.y)
    };
    let odd = IVec2::new(v.x & 1, v.y & 1);
    let k = f64::from(terrain_morph(v.as_uvec2()));
    if !terrain_coarsens(step) || odd == IVec2::ZERO || k == 0.0 {
        return at(v);
    }
    at(v) + k * (0.5 * (at(v - odd) + at(v + odd)) - at(v))
}

/// The drawn terrain's height at grid vertex `v` from its texel in the relief grid (the relief's
/// height, the coarse mesh's height, the normal's x and z): `relief_vertex` in
/// `shaders/common/field.glsl`, on the CPU.
pub fn drawn_grid_height(texel: [f32; 4], v: IVec2, step: f32) -> f32 {
    let k = terrain_morph(v.as_uvec2());
    let odd = ((v.x | v.y) & 1) != 0;
    if terrain_coarsens(step) && odd && k > 0.0 {
        texel[0] * (1.0 - k) + texel[1] * k
    } else {
        texel[0]
    }
}

/// The edge of the drawn terrain's cells under a block cell whose centre lies at grid coordinates
/// `g` (vertex units): the grid's `step`, or two steps where a vertex the cell's ground
/// interpolates may have slid onto the coarse mesh (`terrain_morph`). `cell_spread` of it bounds
/// the cell's roots. Mirrors `field_cell_bounds` in `shaders/common/field.glsl`.
pub fn drawn_step(step: f32, g: Vec2) -> f32 {
    let centre = (gpu::FIELD_TERRAIN_CELLS / 2) as f32;
    let d = (g - Vec2::splat(centre)).abs().max_element();
    // The cell's half edge, the cell of vertices around it and their coarse neighbours.
    let reach = 0.5 * BLOCK_SIZE / step + 2.0;
    if terrain_coarsens(step) && d + reach > gpu::TERRAIN_MORPH_CELLS as f32 {
        2.0 * step
    } else {
        step
    }
}

/// `cell_spread`'s reach per metre of block edge inside the block's square: √½, rounded up
/// (mirrored in `shaders/common/field.glsl`, checked by `tests/shader_sources.rs`).
pub const CELL_SPREAD_INSIDE: f32 = 0.7072;
/// `cell_spread`'s further reach per metre of a coarse terrain cell past half a block: √2,
/// rounded up (mirrored in `shaders/common/field.glsl`).
pub const CELL_SPREAD_OUTSIDE: f32 = 1.4143;

/// The innermost of a block field's nested wind levels (issue #29 item 1; positions relative to
/// O): `WIND_LEVEL_CLUSTERS` clusters of `cluster_size` per side, centred on O's cell. Level l
/// (`wind_level`) has the same corners per side at 2^l times the spacing, about the same centre,
/// so `WIND_LEVELS` levels of 64 one-metre clusters reach 4 096 m from it: 33 800 corners,
/// where one grid over the rings at 150 m held 107 584 (a field holds the levels its blades read,
/// `wind_levels`).
pub fn cluster_grid(cluster_size: f32) -> ClusterGrid {
    wind_level(cluster_size, 0)
}

/// The wind levels that points within `reach` metres (Chebyshev) of O's cell's centre read, as
/// `wind_level_at` of `shaders/wind/wind_field.glsl` picks and blends them: up to the level that
/// holds the farthest, and the one it blends into when it lies in that level's blend band; at
/// most `WIND_LEVELS`.
pub fn levels_reaching(cluster_size: f32, reach: f32) -> u32 {
    let half0 = 0.5 * gpu::WIND_LEVEL_CLUSTERS as f32 * cluster_size;
    let ratio = reach / half0;
    let level = if ratio <= 1.0 { 0 } else { ratio.log2().ceil() as u32 };
    let blended = ratio / (1u32 << level) as f32 > 0.75;
    (level + 1 + u32::from(blended)).min(gpu::WIND_LEVELS)
}

/// The wind levels a block field holds for blades drawn out to `blade_range`: those the cull's
/// rings reach (`ring_radius` blocks about O's cell, whatever the distance test). The corner pass
/// writes only those: at 150 m, 4 levels of 4 225 corners (16 900), not 8 (33 800).
pub fn wind_levels(cluster_size: f32, blade_range: f32) -> u32 {
    levels_reaching(cluster_size, (ring_radius(blade_range) + 1) as f32 * BLOCK_SIZE)
}

/// A block field's wind for blades out to `blade_range`: its innermost level (`cluster_grid`) and
/// the levels it holds (`wind_levels`).
pub fn wind_grid(cluster_size: f32, blade_range: f32) -> (ClusterGrid, u32) {
    (cluster_grid(cluster_size), wind_levels(cluster_size, blade_range))
}

/// Wind level `level` of a block field (`cluster_grid`): `WIND_LEVEL_CLUSTERS` clusters of
/// `cluster_size` · 2^level per side, centred on O's cell.
pub fn wind_level(cluster_size: f32, level: u32) -> ClusterGrid {
    let clusters = gpu::WIND_LEVEL_CLUSTERS;
    let size = cluster_size * (1u32 << level) as f32;
    ClusterGrid { origin: 0.5 * BLOCK_SIZE - 0.5 * clusters as f32 * size, cluster_size: size, clusters }
}

/// The field's part of the frame's uniforms (FrameUniforms' field part, `terrain` and
/// `params.z` re-read for a field as `shaders/common/common.glsl` says). The terrain grid spans
/// the view distance, the rings of blade cells the blade range (`Culling::blade_range`).
pub fn fill_uniforms(
    uniforms: &mut FrameUniforms,
    field: &Field,
    origin: &Origin,
    grid: &ClusterGrid,
    (view_distance, blade_range): (f32, f32),
    verdicts: u32,
) {
    uniforms.relief_waves = field.relief.waves;
    uniforms.relief_phases = field.relief.phases(origin.world);
    let cells = field.spec.cells().unwrap_or(0) as i32;
    uniforms.field_cells = IVec4::new(origin.cell.x, origin.cell.y, cells, 0);
    uniforms.field = Vec4::new(BLOCK_SIZE, field.relief.slope_bound(), grid.origin, grid.origin);
    let step = terrain_step(view_distance);
    let offset = terrain_grid_offset(origin.cell, step);
    uniforms.terrain = Vec4::new(step, grid.cluster_size, offset.x, offset.y);
    let dims = relief_grid_shape(step).dims;
    let base = relief_grid_window(origin.cell, step).rem_euclid(dims.as_i64vec3());
    uniforms.relief_grid = UVec4::new(base.x as u32, base.z as u32, 0, 0);
    uniforms.params.z = gpu::FIELD_TERRAIN_CELLS;
    uniforms.cull_tiles = glam::UVec4::new(verdicts, ring_slots(blade_range), 0, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The height of grid vertex `v` of the grid around O at `o` (world).
    fn vertex_height(relief: &field::Relief, o: DVec2, step: f64, v: IVec2) -> f64 {
        let cell = (o / f64::from(BLOCK_SIZE)).floor().as_ivec2();
        drawn_vertex_height(relief, o, terrain_grid_offset(cell, step as f32), step as f32, v)
    }

    /// The mesh over `corner` (its cell's four vertices' heights) at `f` in the cell, split as
    /// terrain.vert splits it.
    fn split(f: DVec2, corner: impl Fn(i32, i32) -> f64) -> f64 {
        let (h00, h10, h01, h11) = (corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1));
        if f.x >= f.y {
            h00 + f.x * (h10 - h00) + f.y * (h11 - h10)
        } else {
            h00 + f.y * (h01 - h00) + f.x * (h11 - h01)
        }
    }

    /// Where `p` (relative to O at `o`) lies in the grid, in vertex units.
    fn grid_coordinates(o: DVec2, step: f64, p: DVec2) -> DVec2 {
        let cell = (o / f64::from(BLOCK_SIZE)).floor().as_ivec2();
        (p - terrain_grid_offset(cell, step as f32).as_dvec2()) / step
    }

    /// The drawn terrain's height at `p` (relative to O at `o`): the grid's heights at the four
    /// vertices of its cell (`terrain_grid_offset` in field.glsl), split as terrain.vert splits
    /// it: what the cull's roots read (`field_ground_height`).
    fn drawn_height(relief: &field::Relief, o: DVec2, step: f64, p: DVec2) -> f64 {
        let g = grid_coordinates(o, step, p);
        let c = g.floor();
        split(g - c, |dx, dz| vertex_height(relief, o, step, c.as_ivec2() + IVec2::new(dx, dz)))
    }

    /// The coarse mesh's height at `p`: the relief at the four even vertices of the cell of two
    /// steps around `p`, split the same way (a far chunk's coarse range, `terrain_chunks`).
    fn coarse_height(relief: &field::Relief, o: DVec2, step: f64, p: DVec2) -> f64 {
        let g = grid_coordinates(o, step, p) * 0.5;
        let c = g.floor();
        let cell = (o / f64::from(BLOCK_SIZE)).floor().as_ivec2();
        let offset = terrain_grid_offset(cell, step as f32).as_dvec2();
        split(g - c, |dx, dz| {
            let w = (c + DVec2::new(f64::from(dx), f64::from(dz))) * 2.0 * step + offset + o;
            relief.height(w.x, w.y)
        })
    }

    #[test]
    fn the_grid_is_the_coarse_mesh_past_the_morph_and_the_relief_inside_it() {
        // Past TERRAIN_FINE_CELLS the far chunks draw cells of two steps; the grid the fine
        // chunks draw and the roots read is that mesh there (no crack where they meet, roots on
        // the ground as drawn), and the relief's own mesh within TERRAIN_MORPH_CELLS.
        let relief = field::Relief::generate(1);
        let step = terrain_step(150.0);
        assert!(terrain_coarsens(step));
        assert!(!terrain_coarsens(terrain_step(300.0)), "a block of one cell has no even lattice");
        let o = DVec2::new(4.0, -8.0);
        let cell = (o / f64::from(BLOCK_SIZE)).floor().as_ivec2();
        let offset = terrain_grid_offset(cell, step).as_dvec2();
        let centre = f64::from(gpu::FIELD_TERRAIN_CELLS / 2);
        let (mut far, mut near, mut band) = (0, 0, 0.0f64);
        for i in 0..400 {
            // Points along a diagonal spiral out to the grid's edge, in vertex units.
            let angle = f64::from(i) * 0.37;
            let radius = f64::from(i) / 400.0 * (centre - 1.0);
            let g = DVec2::splat(centre) + radius * DVec2::new(angle.cos(), angle.sin());
            let p = g * f64::from(step) + offset;
            let d = (g - DVec2::splat(centre)).abs().max_element();
            let drawn = drawn_height(&relief, o, f64::from(step), p);
            if d >= f64::from(gpu::TERRAIN_FINE_CELLS) {
                let coarse = coarse_height(&relief, o, f64::from(step), p);
                assert!((drawn - coarse).abs() < 1e-9, "{g}: {drawn} off the coarse mesh {coarse}");
                far += 1;
            } else if d + 1.0 < f64::from(gpu::TERRAIN_MORPH_CELLS) {
                let fine = {
                    let c = g.floor();
                    split(g - c, |dx, dz| {
                        let w = (c + DVec2::new(f64::from(dx), f64::from(dz))) * f64::from(step) + offset + o;
                        relief.height(w.x, w.y)
                    })
                };
                assert!((drawn - fine).abs() < 1e-12, "{g}: {drawn} is not the relief's mesh {fine}");
                near += 1;
            } else {
                band = band.max((drawn - coarse_height(&relief, o, f64::from(step), p)).abs());
            }
        }
        assert!(far > 50 && near > 20, "{far} far and {near} near points");
        assert!(band > 1e-3, "the band between moves nothing ({band} m): the test would mean nothing");
    }

    #[test]
    fn a_cells_drawn_terrain_stays_within_its_spread_at_every_grid_step() {
        // The cull's cell and root boxes (field.glsl) bound the roots by the relief at the cell's
        // centre ± `cell_spread`: the roots sit on the drawn terrain, which at view distances past
        // 156 m interpolates vertices outside the cell.
        let relief = field::Relief::generate(1);
        let slope = relief.slope_bound();
        let mut widest = [0.0f64; 4];
        for (k, view) in [40.0, 150.0, 300.0, 600.0].into_iter().enumerate() {
            let step = terrain_step(view);
            for o in [DVec2::ZERO, DVec2::new(4.0, -8.0), DVec2::new(100_012.0, 36.0)] {
                // Near O, in the morph band and in the far chunks (`drawn_step`).
                let cells = [(0, 0), (1, 0), (-3, 2), (5, -7), (7, 3), (-9, -10), (14, -2), (-18, 17)];
                for (cx, cz) in
                    cells.into_iter().filter(|&(x, z): &(i32, i32)| 4.0 * (x.abs().max(z.abs()) as f32) < 38.0 * step)
                {
                    let corner = DVec2::new(f64::from(cx), f64::from(cz)) * f64::from(BLOCK_SIZE);
                    let centre = corner + DVec2::splat(0.5 * f64::from(BLOCK_SIZE));
                    let g = grid_coordinates(o, f64::from(step), centre).as_vec2();
                    let spread = f64::from(cell_spread(slope, drawn_step(step, g)));
                    let mid = relief.height(o.x + centre.x, o.y + centre.y);
                    for i in 0..=16 {
                        for j in 0..=16 {
                            let p = corner + DVec2::new(f64::from(i), f64::from(j)) * f64::from(BLOCK_SIZE) / 16.0;
                            let off = (drawn_height(&relief, o, f64::from(step), p) - mid).abs();
                            assert!(off <= spread, "step {step}: {off} past the spread {spread}");
                            widest[k] = widest[k].max(off);
                        }
                    }
                }
            }
        }
        assert!(widest.iter().all(|&w| w > 0.0));
    }

    #[test]
    fn the_terrain_grid_stays_put_in_the_world_when_o_moves() {
        for view in [40.0, 150.0, 300.0, 500.0] {
            let step = terrain_step(view);
            let mut lattice = None;
            for c in [-25_001, -3, -2, -1, 0, 1, 2, 3, 7, 25_000] {
                let cell = IVec2::new(c, -c);
                let offset = terrain_grid_offset(cell, step).as_dvec2();
                // Vertex 0 in the world, modulo the step (two steps where the far chunks are
                // coarse: their lattice, the even vertices, stays put too): the same for every O.
                let world = cell.as_dvec2() * f64::from(BLOCK_SIZE) + offset;
                let lattice_step = f64::from(if terrain_coarsens(step) { 2.0 * step } else { step });
                let phase = (world.x.rem_euclid(lattice_step), world.y.rem_euclid(lattice_step));
                assert_eq!(*lattice.get_or_insert(phase), phase, "view {view} m, O's cell {cell}");
                // The grid still spans the view distance around O's cell on both sides.
                let first = offset.x.max(offset.y);
                let last = offset.x.min(offset.y) + f64::from(gpu::FIELD_TERRAIN_CELLS) * f64::from(step);
                assert!(
                    first <= -f64::from(view) && last >= f64::from(view + BLOCK_SIZE),
                    "view {view}: {first}..{last}"
                );
            }
        }
    }

    #[test]
    fn coarse_grid_steps_need_the_wider_spread() {
        // One steep wave about 15 m long, across the grid's diagonal, sampled by 8 m cells: the
        // drawn terrain cuts across crests and troughs, and over some cells strays past what
        // cells of half a block allow, never past `cell_spread` for its step.
        let mut relief = field::Relief::generate(1);
        let (m, n) = (880, 1040);
        let k = std::f32::consts::TAU / field::WORLD_PERIOD;
        relief.waves = [Vec4::ZERO; field::WAVES];
        relief.waves[0] = Vec4::new(m as f32 * k, n as f32 * k, 1.0, 0.8);
        relief.cycles[0] = (m, n);
        let slope = relief.slope_bound();
        let step = terrain_step(500.0);
        assert_eq!(step, 8.0);
        let edge = f64::from(BLOCK_SIZE);
        let mut widest = 0.0f64;
        for cx in -4..4 {
            for cz in -4..4 {
                let corner = DVec2::new(f64::from(cx), f64::from(cz)) * edge;
                let mid = relief.height(corner.x + 0.5 * edge, corner.y + 0.5 * edge);
                for i in 0..=8 {
                    for j in 0..=8 {
                        let p = corner + DVec2::new(f64::from(i), f64::from(j)) * edge / 8.0;
                        widest = widest.max((drawn_height(&relief, DVec2::ZERO, f64::from(step), p) - mid).abs());
                    }
                }
            }
        }
        let (fine, coarse) = (f64::from(cell_spread(slope, 2.0)), f64::from(cell_spread(slope, step)));
        assert!(widest > fine, "{widest} within the spread of half-block cells {fine}");
        assert!(widest <= coarse, "{widest} past the spread {coarse}");
    }

    #[test]
    fn origins_are_cell_corners_and_cameras_stay_near_them() {
        let camera = Camera { position: Vec3::new(100_001.5, 2.0, -99_998.5), yaw_deg: 10.0, pitch_deg: -5.0 };
        let o = Origin::under(&camera);
        assert_eq!(o.cell, IVec2::new(25_000, -25_000));
        let rel = o.relative(&camera);
        assert_eq!(rel.position, Vec3::new(1.5, 2.0, 1.5));
        assert!(terrain_step(150.0) * gpu::FIELD_TERRAIN_CELLS as f32 >= 2.0 * 154.0);
        assert_eq!(terrain_step(150.0), 2.0);
        assert_eq!(terrain_step(400.0), 8.0);
        // The wind's levels share a centre, O's cell's, and double their spacing; the outermost
        // covers every ring cell around O's cell at 150 m, and reaches 4 km.
        let reach = ring_radius(150.0) as f32 * BLOCK_SIZE;
        for level in 0..gpu::WIND_LEVELS {
            let grid = wind_level(1.0, level);
            assert_eq!(grid.origin + 0.5 * grid.clusters as f32 * grid.cluster_size, 0.5 * BLOCK_SIZE);
            assert_eq!(grid.cluster_size, (1u32 << level) as f32);
        }
        let outer = wind_level(1.0, gpu::WIND_LEVELS - 1);
        let end = outer.origin + outer.clusters as f32 * outer.cluster_size;
        assert!(outer.origin <= -reach && end >= reach + BLOCK_SIZE && end > 4000.0);
        assert_eq!(cluster_grid(1.0), wind_level(1.0, 0));
        assert_eq!((wind_levels(1.0, 20.0), wind_levels(1.0, 150.0), wind_levels(1.0, 5000.0)), (2, 4, 8));
    }
}
