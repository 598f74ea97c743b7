//! A stored field's ground: its terrain as the clipmap's one level, uploaded with the scene.

use glam::{IVec2, IVec4, UVec4, Vec4};

use super::cover::cover_uniforms;
use super::{GroundFill, GroundSource};
use crate::render::terrain_chunks;
use crate::render::uniforms::FrameUniforms;
use crate::scene::cover::Cover;
use crate::scene::Terrain;

/// A stored field's terrain as the clipmap's one level: its whole grid at its own step, placed at
/// its origin, never moved.
pub struct StoredGround {
    /// The height field.
    pub terrain: Terrain,
    /// Where grass grows (its blades were scattered by it; the terrain is tinted by it).
    pub cover: Cover,
}

impl GroundSource for StoredGround {
    fn cells(&self) -> u32 {
        self.terrain.cells
    }

    fn levels(&self, _: (f32, f32)) -> u32 {
        1
    }

    fn chunk_cells(&self) -> u32 {
        terrain_chunks::CHUNK_CELLS
    }

    fn texel_count(&self) -> u64 {
        u64::from(self.terrain.cells + 1).pow(2) + super::tiles::count(1, self.terrain.cells)
    }

    fn height_range(&self) -> (f32, f32) {
        let heights = &self.terrain.heights;
        heights.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| (lo.min(h), hi.max(h)))
    }

    fn texels(&self) -> Option<Vec<[f32; 4]>> {
        // The level's vertices, then its tiles (`tiles`), from the vertices and their covers as
        // the GPU reads them (packed).
        let mut texels = stored_texels(&self.terrain);
        let covers: Vec<(f32, f32)> = self.packed_covers(&texels).into_iter().map(super::unpack_cover).collect();
        let tiles = super::tiles::tiles_of(self.terrain.cells, &texels, &covers);
        texels.extend(tiles);
        Some(texels)
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms, _: IVec2, _: (f32, f32)) {
        let (origin, step) = (self.terrain.origin(), self.terrain.cell_size());
        uniforms.ground = UVec4::new(self.terrain.cells, 0, 1, 0);
        cover_uniforms(uniforms, &self.cover);
        // Rise over two cells: the central differences (`stored_texels`).
        uniforms.ground_levels[0] = Vec4::new(origin, origin, step, 2.0 * step);
        uniforms.ground_windows[0] = IVec4::ZERO;
    }

    fn fill(&self) -> Option<Box<dyn GroundFill>> {
        None
    }

    fn cover(&self) -> &Cover {
        &self.cover
    }

    fn cover_texels(&self) -> Option<Vec<u32>> {
        Some(self.packed_covers(&stored_texels(&self.terrain)))
    }
}

impl StoredGround {
    /// The covers at the vertices of `texels` (`stored_texels`, row by row from the terrain's
    /// origin), packed (`pack_cover`): at each, the slope by its central differences over two
    /// cells.
    fn packed_covers(&self, texels: &[[f32; 4]]) -> Vec<u32> {
        let (step, run) = (self.terrain.cell_size(), 2.0 * self.terrain.cell_size());
        let (n, origin) = (self.terrain.cells + 1, self.terrain.origin());
        let at = |i: u32| f64::from(origin + (i as f32) * step);
        let density = |(i, t): (usize, &[f32; 4])| {
            let slope = glam::Vec2::new(t[2], t[3]) / run;
            let (x, z) = (at(i as u32 % n), at(i as u32 / n));
            crate::render::ground::pack_cover(self.cover.density(x, z, slope), self.cover.flower_density(x, z, slope))
        };
        texels.iter().enumerate().map(density).collect()
    }
}

/// A stored terrain's texels, row by row (the one level's window has its base at slot 0): the
/// height, the same height as the next level's (there is none, and no morph), and the central
/// differences along x and z over two cells, clamped to the grid, as the terrain's vertices were
/// always lit.
pub fn stored_texels(terrain: &Terrain) -> Vec<[f32; 4]> {
    let n = terrain.cells as i64 + 1;
    let h = |x: i64, z: i64| terrain.heights[(z.clamp(0, n - 1) * n + x.clamp(0, n - 1)) as usize];
    let mut texels = Vec::with_capacity((n * n) as usize);
    for z in 0..n {
        for x in 0..n {
            let height = h(x, z);
            texels.push([height, height, h(x + 1, z) - h(x - 1, z), h(x, z + 1) - h(x, z - 1)]);
        }
    }
    texels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stored_terrains_texels_are_its_heights_and_central_differences() {
        let terrain = Terrain::generate(6.0, 4);
        let texels = stored_texels(&terrain);
        let n = terrain.cells as usize + 1;
        assert_eq!(texels.len(), n * n);
        let h = |x: usize, z: usize| terrain.heights[z * n + x];
        // Inside: the differences over two cells; at the edge, clamped to the grid.
        assert_eq!(texels[2 * n + 3], [h(3, 2), h(3, 2), h(4, 2) - h(2, 2), h(3, 3) - h(3, 1)]);
        assert_eq!(texels[0], [h(0, 0), h(0, 0), h(1, 0) - h(0, 0), h(0, 1) - h(0, 0)]);
        let source = StoredGround { terrain: terrain.clone(), cover: Cover::default() };
        let uploaded = source.texels().expect("uploaded");
        assert_eq!(source.texel_count(), uploaded.len() as u64);
        assert_eq!(uploaded[..n * n], texels[..], "the vertices come first");
        // Then the tiles: the first, over the grid's first 2 × 2 cells, bounds their vertices.
        let first: Vec<f32> = (0..=2).flat_map(|z| (0..=2).map(move |x| h(x, z))).collect();
        let lo = first.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = first.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(uploaded[n * n], [lo, hi, 1.0, 1.0]);
        let mut uniforms: FrameUniforms = bytemuck::Zeroable::zeroed();
        source.fill_uniforms(&mut uniforms, IVec2::ZERO, (150.0, 150.0));
        assert_eq!(uniforms.ground_levels[0], Vec4::new(-3.0, -3.0, terrain.cell_size(), 2.0 * terrain.cell_size()));
        // No slope limit: 10 radians, which no slope reaches; the soft edge's width in radians.
        let soft = crate::scene::cover::SLOPE_SOFT_DEG.to_radians().to_bits();
        assert_eq!(uniforms.ground, UVec4::new(terrain.cells, 10f32.to_bits(), 1, soft));
        // A limit's radians.
        let limited = StoredGround { terrain, cover: Cover { slope_limit_deg: Some(30.0), map: None } };
        limited.fill_uniforms(&mut uniforms, IVec2::ZERO, (150.0, 150.0));
        assert_eq!(uniforms.ground.y, 30f32.to_radians().to_bits());
    }
}
