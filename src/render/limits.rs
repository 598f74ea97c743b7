//! The ranges a renderer's settings must lie in, for the code below `render::settings` that sizes
//! or checks by them (the cull's LOD segments, the visible list's padding) and for the command
//! line's parsers; `render::settings` re-exports them with the settings they bound.

/// Blade segments allowed (thesis 4.1 levels of detail).
pub const SEGMENTS_RANGE: std::ops::RangeInclusive<u32> = 1..=crate::render::gpu_constants::MAX_SEGMENTS;

/// Blades per instance allowed.
pub const BLADES_PER_INSTANCE_RANGE: std::ops::RangeInclusive<u32> = 1..=1024;

/// The longest `--view-distance` in metres: the ground's extent (a block field's terrain grid, of
/// `FIELD_TERRAIN_CELLS` cells, grows its cells to span it). `scene::field::WORLD_PERIOD` is
/// twice it.
pub const MAX_VIEW_DISTANCE: f32 = 10_000.0;
const _: () = assert!(2.0 * MAX_VIEW_DISTANCE <= crate::scene::field::WORLD_PERIOD);
