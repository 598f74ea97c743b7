//! A block field on a heightmap: the relief's clipmap, filled from the map's texels.

use std::sync::Arc;

use glam::IVec2;

use super::cover::{cover_map_words, cover_uniforms};
use super::relief::{clipmap_uniforms, ClipmapFill};
use super::{GroundFill, GroundSource};
use crate::render::shaders;
use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;
use crate::scene::heightmap::Heightmap;

/// A block field on a heightmap (`scene::heightmap`): the relief's clipmap, filled from the map's
/// texels (`shaders/terrain/heightmap_fill.comp`), which live on the GPU at 2 bytes each
/// (`GroundMap`: a header, then two texels a word).
pub struct HeightmapGround {
    /// The map.
    pub map: Arc<Heightmap>,
    /// Where grass grows on it.
    pub cover: Cover,
}

/// Words of `GroundMap`'s header: width, height, the extent in x and z and the height of white
/// (f32 bits), whether the map repeats mirrored (1) or is clamped past its edges (0).
pub const MAP_HEADER_WORDS: usize = 8;

impl GroundSource for HeightmapGround {
    fn height_range(&self) -> (f32, f32) {
        (0.0, self.map.scale.y as f32)
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, cell: IVec2, distances: (f32, f32)) {
        clipmap_uniforms(uniforms, cell, distances);
        cover_uniforms(uniforms, &self.cover);
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        Some(Box::new(ClipmapFill { shader: shaders::HEIGHTMAP_FILL_COMP }))
    }

    fn buffers(&self) -> Vec<(&'static str, Vec<u32>)> {
        vec![("GroundMap", map_words(&self.map)), ("CoverMap", cover_map_words(&self.cover))]
    }
}

/// `GroundMap`'s words for `map` (`MAP_HEADER_WORDS`, then its texels two a word, the first in
/// the low half).
pub fn map_words(map: &Heightmap) -> Vec<u32> {
    let s = map.scale;
    let header = [map.width, map.height, (s.x as f32).to_bits(), (s.z as f32).to_bits(), (s.y as f32).to_bits()];
    let mut words = Vec::with_capacity(MAP_HEADER_WORDS + map.texels.len().div_ceil(2));
    words.extend_from_slice(&header);
    words.extend([u32::from(map.mirrored), 0, 0]);
    words.extend(map.texels.chunks(2).map(|t| u32::from(t[0]) | (u32::from(*t.get(1).unwrap_or(&0)) << 16)));
    words
}
