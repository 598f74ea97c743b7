//! A block field's procedural relief in the clipmap's nested levels, filled on the GPU as the
//! camera moves (`relief_fill.comp`); its fill, [`ClipmapFill`], serves the heightmap too.

use glam::{I64Vec3, IVec2, IVec4, UVec4, Vec4};

use super::cover::{cover_map_words, cover_uniforms};
use super::{GroundFill, GroundSource};
use crate::render::camera_grid::GridShape;
use crate::render::ground_clipmap::{self, Clipmap};
use crate::render::shaders;
use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;
use crate::scene::field;
use crate::vk::profile::Shader;

/// A block field's relief in nested levels around the camera (`ground_clipmap::Clipmap`), filled
/// as the camera moves.
pub struct ReliefGround {
    /// The relief, evaluated anywhere.
    pub relief: field::Relief,
    /// Where grass grows on it.
    pub cover: Cover,
}

impl GroundSource for ReliefGround {
    fn height_range(&self) -> (f32, f32) {
        let bound = self.relief.height_bound();
        (-bound, bound)
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, cell: IVec2, distances: (f32, f32)) {
        clipmap_uniforms(uniforms, cell, distances);
        cover_uniforms(uniforms, &self.cover);
        // Taken mod the period in half-metres, so the fill's products fit 32 bits unsigned.
        let residue = |c: i32| c.rem_euclid(ground_clipmap::PERIOD_HALF_METRES as i32);
        uniforms.relief_cycles = std::array::from_fn(|i| {
            let (a, b) = (self.relief.cycles[2 * i], self.relief.cycles[2 * i + 1]);
            IVec4::new(residue(a.0), residue(a.1), residue(b.0), residue(b.1))
        });
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        Some(Box::new(ClipmapFill { shader: shaders::RELIEF_FILL_COMP }))
    }

    fn buffers(&self) -> Vec<(&'static str, Vec<u32>)> {
        vec![("CoverMap", cover_map_words(&self.cover))]
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }
}

/// A block field's clipmap for O's cell `cell` and the (view distance, blade range), as the
/// relief and the heightmap write it into the frame's uniforms: each texel's rise is its slope,
/// over a run of 1 m.
pub(super) fn clipmap_uniforms(uniforms: &mut FrameUniforms, cell: IVec2, (view_distance, blade_range): (f32, f32)) {
    let clipmap = Clipmap::for_view(view_distance, blade_range);
    let (levels, windows) = clipmap.uniforms(cell);
    uniforms.ground_levels = levels.map(|l| Vec4::new(l.x, l.y, l.z, 1.0));
    uniforms.ground_windows = windows;
    uniforms.ground = UVec4::new(ground_clipmap::CELLS, 0, clipmap.levels, 0);
}

/// The fill of a block field's clipmap by `shader` (the relief's `relief_fill.comp`, the
/// heightmap's `heightmap_fill.comp`): its clipmap is read back from the frame's uniforms, level
/// 0's step and the levels, and the relief's waves are what else its texels depend on.
pub(super) struct ClipmapFill {
    pub(super) shader: Shader,
}

impl ClipmapFill {
    fn clipmap(uniforms: &FrameUniforms) -> Clipmap {
        Clipmap { step: uniforms.ground_levels[0].z, levels: uniforms.ground.z.max(1) }
    }
}

impl GroundFill for ClipmapFill {
    fn shader(&self) -> Shader {
        self.shader
    }

    fn shape(&self, uniforms: &FrameUniforms) -> GridShape {
        Self::clipmap(uniforms).shape()
    }

    fn key(&self, uniforms: &FrameUniforms) -> Vec<u32> {
        let clipmap = Self::clipmap(uniforms);
        let waves = uniforms.relief_waves.iter().flat_map(|w| w.to_array().map(f32::to_bits));
        let cycles = uniforms.relief_cycles.iter().flat_map(|c| c.to_array().map(|v| v as u32));
        [clipmap.step.to_bits(), clipmap.levels].into_iter().chain(waves).chain(cycles).collect()
    }

    fn windows(&self, uniforms: &FrameUniforms) -> Vec<I64Vec3> {
        let cell = IVec2::new(uniforms.field_cells.x, uniforms.field_cells.y);
        Self::clipmap(uniforms).windows(cell).into_iter().map(ground_clipmap::grid_window).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reliefs_buffer_holds_its_clipmap_at_any_view_distance() {
        let relief = field::Relief::generate(1);
        let source = ReliefGround { relief, cover: Cover::default() };
        for view in [40.0, 150.0, 5000.0, 10_000.0] {
            let mut uniforms: FrameUniforms = bytemuck::Zeroable::zeroed();
            source.fill_uniforms(&mut uniforms, IVec2::new(3, -7), (view, view.min(150.0)));
            let fill = source.fill().expect("a relief fills on the GPU");
            let shape = fill.shape(&uniforms);
            assert!(shape.cells_per_level() * u64::from(shape.levels) <= source.texel_count(), "{view} m");
            assert_eq!(fill.windows(&uniforms).len() as u32, shape.levels);
            assert!(uniforms.ground_levels[..shape.levels as usize].iter().all(|l| l.w == 1.0));
        }
    }
}
