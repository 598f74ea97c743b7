//! A block field on the GPU (`scene::field`, Belyaev §2.1): the origin O each frame (the corner of
//! the block cell under the camera), the cameras relative to it, the grid of force corners that
//! follows it, and the field's part of the frame's uniforms. Everything the GPU sees is relative
//! to O, so a field 100 km from the world's origin renders as one at the origin does.

use glam::{DVec2, IVec2, IVec4, Vec3, Vec4};

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

/// The field's part of the frame's uniforms (FrameUniforms' field part, and `terrain.y` re-read
/// as the innermost wind level's cluster edge, as `shaders/common/common.glsl` says); the rings of
/// blade cells span the blade range (`Culling::blade_range`). The ground's part is its source's
/// (`render::ground::ReliefGround`).
pub fn fill_uniforms(
    uniforms: &mut FrameUniforms,
    field: &Field,
    origin: &Origin,
    grid: &ClusterGrid,
    blade_range: f32,
) {
    if let Some(relief) = field.ground.relief() {
        // The relief's fill (`relief_fill.comp`) and its cells' bounds read its waves.
        uniforms.relief_waves = relief.waves;
        uniforms.relief_phases = relief.phases(origin.world);
    }
    let cells = field.spec.cells().unwrap_or(0) as i32;
    uniforms.field_cells = IVec4::new(origin.cell.x, origin.cell.y, cells, 0);
    uniforms.field = Vec4::new(BLOCK_SIZE, field.ground.slope_bound(), grid.origin, grid.origin);
    uniforms.terrain = Vec4::new(0.0, grid.cluster_size, 0.0, 0.0);
    uniforms.cull_tiles = glam::UVec4::new(0, ring_slots(blade_range), 0, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn origins_are_cell_corners_and_cameras_stay_near_them() {
        let camera = Camera { position: Vec3::new(100_001.5, 2.0, -99_998.5), yaw_deg: 10.0, pitch_deg: -5.0 };
        let o = Origin::under(&camera);
        assert_eq!(o.cell, IVec2::new(25_000, -25_000));
        let rel = o.relative(&camera);
        assert_eq!(rel.position, Vec3::new(1.5, 2.0, 1.5));
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
