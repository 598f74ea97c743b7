//! The CPU scene: terrain, blades, camera. Built once from a seed, then uploaded to GPU buffers.

pub mod alpha;
pub mod bezier;
pub mod blades;
pub mod camera;
pub mod clusters;
pub mod rng;
pub mod terrain;
pub mod tiles;

pub use blades::BladeInstance;
pub use camera::Camera;
pub use terrain::Terrain;

/// Terrain and blades of one field.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The height field.
    pub terrain: Terrain,
    /// Every blade, tile by tile (`tiles::arrange`).
    pub blades: Vec<BladeInstance>,
    /// The tiles over the field.
    pub tile_grid: tiles::TileGrid,
    /// One record per tile of `tile_grid`, row-major.
    pub tiles: Vec<tiles::BladeTile>,
}

impl Scene {
    /// Build the field for `blade_count` blades from `seed`.
    pub fn generate(blade_count: u32, seed: u64) -> Self {
        let terrain = Terrain::generate(blades::field_size(blade_count), seed);
        let mut blades = blades::scatter(&terrain, blade_count, seed);
        let tile_grid = tiles::TileGrid::new(terrain.size);
        let tiles = tiles::arrange(&tile_grid, &mut blades);
        Self { terrain, blades, tile_grid, tiles }
    }
}
