//! The cover channel every source writes beside its texels (`scene::cover`): the frame's slope
//! limit and the covering map's words the fills read (`shaders/terrain/cover_fill.glsl`).

use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;

/// The cover rules' part of the frame's `ground` (`shaders/terrain/cover_fill.glsl`): y the slope
/// limit, w its soft edge's width, radians as f32 bits; without a limit, 10 radians (no slope
/// reaches it).
pub(super) fn cover_uniforms(uniforms: &mut FrameUniforms, cover: &Cover) {
    let limit = cover.slope_limit_deg.map_or(10.0, f32::to_radians);
    uniforms.ground.y = limit.to_bits();
    uniforms.ground.w = crate::scene::cover::SLOPE_SOFT_DEG.to_radians().to_bits();
}

/// Words of `CoverMap`'s header: width, height, the extent in x and z (f32 bits), whether the
/// map repeats mirrored (1) or is held past its edges (0).
pub const COVER_MAP_HEADER_WORDS: usize = 8;

/// `CoverMap`'s words for `cover`'s covering map (`shaders/terrain/cover_fill.glsl`):
/// `COVER_MAP_HEADER_WORDS` (width, height, extent x and z as f32 bits, mirrored, the flower
/// plane's first word), then its grass densities four a word, the first in the low byte, then its
/// flower densities likewise. Without a map, a 1 × 1 map of full density.
pub fn cover_map_words(cover: &Cover) -> Vec<u32> {
    let full = [255u8];
    let (width, height, grass, flowers, placement) = match &cover.map {
        Some(m) => (m.width, m.height, m.grass.as_slice(), m.flowers.as_slice(), m.placement),
        None => (1, 1, &full[..], &full[..], crate::scene::cover::MapPlacement { x: 1.0, z: 1.0, mirrored: true }),
    };
    let (x, z) = ((placement.x as f32).to_bits(), (placement.z as f32).to_bits());
    let plane = grass.len().div_ceil(4);
    let mut words = Vec::with_capacity(COVER_MAP_HEADER_WORDS + 2 * plane);
    let flower_plane = (COVER_MAP_HEADER_WORDS + plane) as u32;
    words.extend([width, height, x, z, u32::from(placement.mirrored), flower_plane, 0, 0]);
    for densities in [grass, flowers] {
        words.extend(densities.chunks(4).map(|c| c.iter().rev().fold(0u32, |w, &b| (w << 8) | u32::from(b))));
    }
    words
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;

    #[test]
    fn the_cover_maps_words_hold_its_header_and_its_densities_four_a_word() {
        let placement = crate::scene::cover::MapPlacement { x: 200.0, z: 100.0, mirrored: false };
        let map = crate::scene::cover::CoverMap {
            width: 5,
            height: 1,
            grass: vec![1, 2, 3, 4, 5],
            flowers: vec![6, 7, 8, 9, 10],
            placement,
        };
        let words = cover_map_words(&Cover { slope_limit_deg: None, map: Some(Arc::new(map)) });
        assert_eq!(words[..6], [5, 1, 200f32.to_bits(), 100f32.to_bits(), 0, 10]);
        assert_eq!(words[COVER_MAP_HEADER_WORDS..], [0x0403_0201, 5, 0x0908_0706, 10]);
        // No map: one texel of full density.
        let none = cover_map_words(&Cover::default());
        assert_eq!((none[0], none[1], none[COVER_MAP_HEADER_WORDS]), (1, 1, 255));
        assert_eq!(none[none[5] as usize], 255, "full flower density");
    }
}
