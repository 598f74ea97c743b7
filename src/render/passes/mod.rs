//! Render passes, one per file. Each owns its pipeline and records its draws into the scene's
//! rendering instance.

pub mod blade_pose;
pub mod blades;
pub mod floor;
pub mod terrain;

pub use blade_pose::BladePosePass;
pub use blades::BladePass;
pub use floor::FloorPass;
pub use terrain::TerrainPass;
