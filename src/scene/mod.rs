//! The CPU scene: terrain, blades, camera. Built once from a seed, then uploaded to GPU buffers.

pub mod alpha;
pub mod bezier;
pub mod blades;
pub mod camera;
pub mod clusters;
pub mod rng;
pub mod terrain;

pub use blades::BladeInstance;
pub use camera::Camera;
pub use terrain::Terrain;

/// Terrain and blades of one field.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The height field.
    pub terrain: Terrain,
    /// Every blade.
    pub blades: Vec<BladeInstance>,
}

impl Scene {
    /// Build the field for `blade_count` blades from `seed`.
    pub fn generate(blade_count: u32, seed: u64) -> Self {
        let terrain = Terrain::generate(blades::field_size(blade_count), seed);
        let blades = blades::scatter(&terrain, blade_count, seed);
        Self { terrain, blades }
    }
}
