//! The clipmap's tiles (issue #30 item 2): per level, square tiles of `GROUND_TILE_CELLS` cells
//! from the window's first vertex, each holding the lowest and highest height of its vertices'
//! texels (a texel's own height and the next level's mesh there, between which a drawn vertex
//! slides), and the most grass and flower cover at them. The cull bounds a block cell's heights by
//! the tiles under it and skips a cell whose tiles have no cover (`ground_tile_bounds` in
//! `shaders/common/ground.glsl`), whatever the source. Their texels follow every level's vertices
//! in the clipmap's buffer (`shaders/terrain/ground_texels.glsl`). A filled source's tiles are
//! written on the GPU after each fill (`shaders/terrain/ground_tiles.comp`, the last step of
//! `passes::ground_fill`), an uploaded one's here ([`tiles_of`]).

use crate::render::gpu_constants::GROUND_TILE_CELLS;

/// Tiles per side of a level of `cells` cells.
pub fn per_side(cells: u32) -> u32 {
    cells.div_ceil(GROUND_TILE_CELLS)
}

/// Tile texels of `levels` levels of `cells` cells.
pub fn count(levels: u32, cells: u32) -> u64 {
    u64::from(levels) * u64::from(per_side(cells)).pow(2)
}

/// The texel of tile (`x`, `z`) of `level`, in a clipmap of `levels` levels of `cells` cells
/// (`ground_tile_texel`): after the levels' vertices.
pub fn texel(levels: u32, cells: u32, level: u32, (x, z): (u32, u32)) -> usize {
    let n = cells as usize + 1;
    let t = per_side(cells) as usize;
    levels as usize * n * n + (level as usize * t + z as usize) * t + x as usize
}

/// The tiles of one level of `cells` cells whose vertices' texels (in slot order, row by row from
/// the window's first vertex: an uploaded level's) are `texels`, their covers (grass, flowers)
/// `covers`: row by row, x the lowest height, y the highest, z and w the most covers.
pub fn tiles_of(cells: u32, texels: &[[f32; 4]], covers: &[(f32, f32)]) -> Vec<[f32; 4]> {
    let n = cells as usize + 1;
    let t = per_side(cells);
    let step = GROUND_TILE_CELLS as usize;
    let mut tiles = Vec::with_capacity((t * t) as usize);
    for tz in 0..t as usize {
        for tx in 0..t as usize {
            let mut bounds = [f32::INFINITY, f32::NEG_INFINITY, 0.0f32, 0.0f32];
            for z in tz * step..=((tz + 1) * step).min(n - 1) {
                for x in tx * step..=((tx + 1) * step).min(n - 1) {
                    let (texel, cover) = (texels[z * n + x], covers[z * n + x]);
                    bounds[0] = bounds[0].min(texel[0].min(texel[1]));
                    bounds[1] = bounds[1].max(texel[0].max(texel[1]));
                    bounds[2] = bounds[2].max(cover.0);
                    bounds[3] = bounds[3].max(cover.1);
                }
            }
            tiles.push(bounds);
        }
    }
    tiles
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tile_holds_the_range_of_its_vertices_its_edges_shared_with_its_neighbours() {
        assert_eq!(GROUND_TILE_CELLS, 2, "the figures below are for tiles of 2 cells");
        // 3 cells: tiles of 2 and of 1 cell per side; 4 × 4 vertices of height x + 100 z.
        let (cells, n) = (3u32, 4usize);
        let texels: Vec<[f32; 4]> =
            (0..n * n).map(|i| [(i % n) as f32 + 100.0 * (i / n) as f32, 0.5, 0.0, 0.0]).collect();
        let covers: Vec<(f32, f32)> = (0..n * n).map(|i| if i == n + 3 { (0.25, 1.0) } else { (0.0, 0.0) }).collect();
        let tiles = tiles_of(cells, &texels, &covers);
        assert_eq!(per_side(cells), 2);
        assert_eq!(tiles.len(), 4);
        // Tile (0, 0): vertices 0..=2 both ways, from the vertex (0, 0) at 0 to (2, 2) at 202.
        assert_eq!(tiles[0], [0.0, 202.0, 0.0, 0.0]);
        // Tile (1, 0): x 2..=3, z 0..=2; it holds the covered vertex (3, 1), and the next level's
        // 0.5 is lower than its lowest.
        assert_eq!(tiles[1], [0.5, 203.0, 0.25, 1.0]);
        // Tile (0, 1): z 2..=3 shares row 2 with tile (0, 0).
        assert_eq!(tiles[2], [0.5, 302.0, 0.0, 0.0]);
        assert_eq!(texel(1, cells, 0, (1, 1)), n * n + 3);
        assert_eq!(count(3, 80), 4800);
    }
}
