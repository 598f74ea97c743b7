//! The terrain grid in square chunks of cells, each a contiguous range of the index list, so the
//! terrain pass draws only the chunks whose boxes meet the view frustum (tested on the CPU from
//! the frame's view-projection: the grid's placement and the terrain's height range give each
//! chunk's box). llvmpipe shades every vertex and clips every triangle of a draw on the queue's
//! one thread, on screen or not: at the unbounded field's default view (`meadow timing`, four
//! alternating runs of 20 frames) the terrain's vertex shader invocations fell from 50 160 to
//! 10 521 and the terrain pass from 6.2–6.6 to 5.5–5.6 ms, the picture bit-identical.
//!
//! A block field's ground is the levels of its clipmap (`render::ground_clipmap`), each a grid
//! of `FIELD_TERRAIN_CELLS` cells drawn with the same index list: a level draws its chunks in
//! view but those of its hole, the square its finer level draws, which is a whole number of
//! chunks ([`visible_runs`]'s `hole`).

use glam::{Mat4, Vec3, Vec4};

use crate::render::gpu_constants as gpu;

/// Cells per side of a stored terrain's chunk (the last row and column of chunks may be narrower).
pub const CHUNK_CELLS: u32 = 16;
/// Cells per side of a chunk of a block field's clipmap level: its hole is a whole number of them.
pub const GROUND_CHUNK_CELLS: u32 = 8;

const _: () = assert!(gpu::FIELD_TERRAIN_CELLS.is_multiple_of(2 * GROUND_CHUNK_CELLS));

/// The chunk edge of a block field's clipmap level (`blocks`) or of a stored terrain.
pub fn chunk_cells(blocks: bool) -> u32 {
    if blocks {
        GROUND_CHUNK_CELLS
    } else {
        CHUNK_CELLS
    }
}

/// One chunk: its cells `lo..hi` (x, z) and its ranges of the index list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerrainChunk {
    /// First cell (x, z).
    pub lo: [u32; 2],
    /// One past the last cell (x, z).
    pub hi: [u32; 2],
    /// First index of the chunk's triangles in `chunked_indices`.
    pub first_index: u32,
    /// Indices of its triangles (6 per cell).
    pub index_count: u32,
}

/// The chunks of `chunk` cells per side of a grid of `cells` per side, row by row of chunks.
pub fn chunks(cells: u32, chunk: u32) -> Vec<TerrainChunk> {
    let per_side = cells.div_ceil(chunk);
    let mut first_index = 0;
    let mut out = Vec::with_capacity((per_side * per_side) as usize);
    for cz in 0..per_side {
        for cx in 0..per_side {
            let lo = [cx * chunk, cz * chunk];
            let hi = [(lo[0] + chunk).min(cells), (lo[1] + chunk).min(cells)];
            let index_count = 6 * (hi[0] - lo[0]) * (hi[1] - lo[1]);
            out.push(TerrainChunk { lo, hi, first_index, index_count });
            first_index += index_count;
        }
    }
    out
}

/// The terrain's triangle list, chunk by chunk (`chunks`) and row by row of cells inside a chunk:
/// vertex (x, z) of the `(cells + 1)²` grid is `z (cells + 1) + x`, and a cell splits into
/// (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), as `scene::terrain::Terrain::height_at` and the
/// clipmap's drawn mesh (`terrain_mesh_height` in field.glsl) split it.
pub fn chunked_indices(cells: u32, chunk: u32) -> Vec<u32> {
    let row = cells + 1;
    let mut indices = Vec::with_capacity(6 * (cells * cells) as usize);
    for chunk in &chunks(cells, chunk) {
        for z in chunk.lo[1]..chunk.hi[1] {
            for x in chunk.lo[0]..chunk.hi[0] {
                let v = z * row + x;
                indices.extend_from_slice(&[v, v + 1, v + row + 1, v, v + row + 1, v + row]);
            }
        }
    }
    indices
}

/// Where the grid lies: vertex (x, z) at `offset + (x, z) · step`, heights within `heights`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPlacement {
    /// World (x, z) of vertex (0, 0).
    pub offset: [f32; 2],
    /// Cell edge in metres.
    pub step: f32,
    /// Lowest and highest terrain height (metres).
    pub heights: (f32, f32),
}

impl GridPlacement {
    /// The box of `chunk`'s vertices.
    pub fn chunk_box(&self, chunk: &TerrainChunk) -> (Vec3, Vec3) {
        let at =
            |cell: [u32; 2]| (self.offset[0] + cell[0] as f32 * self.step, self.offset[1] + cell[1] as f32 * self.step);
        let (x0, z0) = at(chunk.lo);
        let (x1, z1) = at(chunk.hi);
        (Vec3::new(x0, self.heights.0, z0), Vec3::new(x1, self.heights.1, z1))
    }
}

/// The planes of the view frustum a chunk must meet, from Vulkan's clip volume of `view_proj`
/// (−w ≤ x, y ≤ w; reversed Z, so the near plane is z ≤ w; the far plane is at infinity): a point
/// p is inside plane n when n · (p, 1) ≥ 0.
pub fn frustum_planes(view_proj: &Mat4) -> [Vec4; 5] {
    let row = |i: usize| view_proj.row(i);
    let (x, y, z, w) = (row(0), row(1), row(2), row(3));
    [w + x, w - x, w + y, w - y, w - z]
}

/// Whether the box `lo..hi` may meet the frustum: false only when it lies wholly outside one
/// plane (conservative: a box outside the frustum near a corner may still pass).
pub fn box_meets_frustum(planes: &[Vec4; 5], lo: Vec3, hi: Vec3) -> bool {
    planes.iter().all(|plane| {
        // The box's corner farthest along the plane's normal.
        let p = Vec3::select(plane.truncate().cmpge(Vec3::ZERO), hi, lo);
        plane.truncate().dot(p) + plane.w >= 0.0
    })
}

/// The runs of consecutive chunks that meet the frustum, as (first index, index count) of one
/// draw each; `hole`: the first cell of a square of `FIELD_TERRAIN_CELLS / 2` cells per side
/// whose chunks are not drawn (a clipmap level's, which the finer level draws).
pub fn visible_runs(
    chunks: &[TerrainChunk],
    placement: &GridPlacement,
    view_proj: &Mat4,
    hole: Option<[u32; 2]>,
) -> Vec<(u32, u32)> {
    let planes = frustum_planes(view_proj);
    let holed = |chunk: &TerrainChunk| {
        hole.is_some_and(|h| {
            let end = gpu::FIELD_TERRAIN_CELLS / 2;
            (0..2).all(|a| chunk.lo[a] >= h[a] && chunk.hi[a] <= h[a] + end)
        })
    };
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for chunk in chunks {
        let (lo, hi) = placement.chunk_box(chunk);
        if holed(chunk) || !box_meets_frustum(&planes, lo, hi) {
            continue;
        }
        let (start, n) = (chunk.first_index, chunk.index_count);
        match runs.last_mut() {
            Some((first, count)) if *first + *count == start => *count += n,
            _ => runs.push((start, n)),
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::camera::Camera;
    use std::collections::HashSet;

    fn triangles(indices: &[u32]) -> HashSet<[u32; 3]> {
        indices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect()
    }

    /// The chunked list holds the row-major grid's triangles, each once, in the chunks' ranges.
    #[test]
    fn chunks_cover_every_cell_once() {
        for cells in [1, 15, 16, 17, 64, 160] {
            let row = cells + 1;
            let row_major: Vec<u32> = (0..cells * cells)
                .flat_map(|cell| {
                    let v = (cell / cells) * row + cell % cells;
                    [v, v + 1, v + row + 1, v, v + row + 1, v + row]
                })
                .collect();
            let chunked = chunked_indices(cells, CHUNK_CELLS);
            assert_eq!(chunked.len(), row_major.len(), "{cells} cells");
            assert_eq!(triangles(&chunked), triangles(&row_major), "{cells} cells");
            let all = chunks(cells, CHUNK_CELLS);
            let total: u32 = all.iter().map(|c| c.index_count).sum();
            assert_eq!(total as usize, chunked.len());
            for chunk in &all {
                let range = &chunked[chunk.first_index as usize..(chunk.first_index + chunk.index_count) as usize];
                for &v in range {
                    let (x, z) = (v % row, v / row);
                    assert!((chunk.lo[0]..=chunk.hi[0]).contains(&x) && (chunk.lo[1]..=chunk.hi[1]).contains(&z));
                }
            }
        }
    }

    /// A level's hole leaves out exactly the chunks of its square, and the rest are drawn.
    #[test]
    fn a_hole_leaves_out_its_chunks() {
        let cells = gpu::FIELD_TERRAIN_CELLS;
        let all = chunks(cells, GROUND_CHUNK_CELLS);
        let placement = GridPlacement { offset: [-320.0, -320.0], step: 4.0, heights: (-2.0, 2.5) };
        // From high above, every chunk is in view.
        let camera = Camera { position: Vec3::new(0.0, 5000.0, 0.0), yaw_deg: 0.0, pitch_deg: -89.9 };
        let view_proj = camera.view_projection(1.0);
        let count = |hole| visible_runs(&all, &placement, &view_proj, hole).iter().map(|r| r.1).sum::<u32>();
        let whole = count(None);
        assert_eq!(whole, 6 * cells * cells);
        for hole in [[16, 24], [24, 16], [16, 16]] {
            assert_eq!(count(Some(hole)), 6 * (cells * cells - (cells / 2) * (cells / 2)), "{hole:?}");
        }
    }

    /// Every grid vertex inside the clip volume belongs to a drawn chunk, for cameras looking
    /// along the grid, across it, down from above and out of it at a corner; and the test drops chunks
    /// (it would be useless otherwise).
    #[test]
    fn the_drawn_chunks_hold_every_vertex_in_view() {
        let cells = 160;
        let placement = GridPlacement { offset: [-320.0, -320.0], step: 4.0, heights: (-2.0, 2.5) };
        let height = |x: u32, z: u32| -2.0 + 4.5 * (((x * 7 + z * 13) % 17) as f32 / 16.0);
        let cameras = [
            Camera { position: Vec3::new(0.0, 1.7, 0.0), yaw_deg: 0.0, pitch_deg: -12.0 },
            Camera { position: Vec3::new(10.0, 3.0, -40.0), yaw_deg: 135.0, pitch_deg: -5.0 },
            Camera { position: Vec3::new(0.0, 80.0, 0.0), yaw_deg: 30.0, pitch_deg: -80.0 },
            Camera { position: Vec3::new(-300.0, 2.0, -300.0), yaw_deg: 45.0, pitch_deg: -20.0 },
        ];
        let all = chunks(cells, CHUNK_CELLS);
        for camera in cameras {
            let view_proj = camera.view_projection(16.0 / 9.0);
            let runs = visible_runs(&all, &placement, &view_proj, None);
            let drawn = |chunk: &TerrainChunk| runs.iter().any(|&(f, n)| (f..f + n).contains(&chunk.first_index));
            let drawn_chunks = all.iter().filter(|c| drawn(c)).count();
            assert!(drawn_chunks < all.len(), "{camera:?}: no chunk culled");
            assert!(drawn_chunks > 0, "{camera:?}: every chunk culled");
            for z in 0..=cells {
                for x in 0..=cells {
                    let p = Vec3::new(
                        placement.offset[0] + x as f32 * placement.step,
                        height(x, z),
                        placement.offset[1] + z as f32 * placement.step,
                    );
                    let clip = view_proj * p.extend(1.0);
                    let inside = clip.w > 0.0
                        && clip.x.abs() <= clip.w
                        && clip.y.abs() <= clip.w
                        && clip.z <= clip.w
                        && clip.z >= 0.0;
                    if !inside {
                        continue;
                    }
                    // The chunks this vertex is a corner of.
                    let owners: Vec<&TerrainChunk> = all
                        .iter()
                        .filter(|c| (c.lo[0]..=c.hi[0]).contains(&x) && (c.lo[1]..=c.hi[1]).contains(&z))
                        .collect();
                    assert!(
                        owners.iter().all(|c| drawn(c)),
                        "{camera:?}: vertex ({x}, {z}) in view, a chunk of it culled"
                    );
                }
            }
        }
    }
}
