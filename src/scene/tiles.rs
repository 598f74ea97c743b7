//! Spatial tiles: the field split into square tiles, the unit the cull pass tests first (Zhang
//! Xia §5.1–5.2 grass grids, thesis §5.3). The blades of a tile are contiguous in the blade
//! buffer, in a progressive order inside it (`progressive_order`), so the first k blades of a tile
//! are an even thinning of the whole tile: the density LOD keeps a prefix (Belyaev §2.2).

use bytemuck::{Pod, Zeroable};

use crate::scene::blades::MAX_WIDENING;
use crate::scene::BladeInstance;

/// Smallest tile edge in metres.
pub const MIN_TILE_SIZE: f32 = 2.0;
/// Most tiles per side: the cull dispatches one workgroup per slot of the rings around the
/// camera's tile, at most `(2 · MAX_TILES_PER_SIDE + 1)²`, well under
/// `maxComputeWorkGroupCount[0]` (65 535 on every device).
pub const MAX_TILES_PER_SIDE: u32 = 64;

/// One tile as the cull pass reads it (`shaders/common/common.glsl`, `BladeTile`): 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BladeTile {
    /// Lower corner of the bounding box of every blade of the tile in any pose.
    pub min: [f32; 3],
    /// Index of the tile's first blade in the blade buffer.
    pub first: u32,
    /// Upper corner of the bounding box.
    pub max: [f32; 3],
    /// Blades in the tile.
    pub count: u32,
}

const _: () = assert!(std::mem::size_of::<BladeTile>() == 32);

/// The square grid of tiles over a field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileGrid {
    /// World x (= z) of the grid's first corner.
    pub origin: f32,
    /// Tile edge in metres.
    pub tile_size: f32,
    /// Tiles per side.
    pub tiles: u32,
}

impl TileGrid {
    /// Tiles of at least `MIN_TILE_SIZE` metres, at most `MAX_TILES_PER_SIDE` per side, covering
    /// a square field of side `field` exactly.
    pub fn new(field: f32) -> Self {
        let tiles = ((field / MIN_TILE_SIZE).floor() as u32).clamp(1, MAX_TILES_PER_SIDE);
        Self { origin: -0.5 * field, tile_size: field / tiles as f32, tiles }
    }

    /// Tile (column, row) holding world (x, z), clamped to the grid.
    pub fn cell(&self, x: f32, z: f32) -> (u32, u32) {
        let at = |v: f32| (((v - self.origin) / self.tile_size).floor().max(0.0) as u32).min(self.tiles - 1);
        (at(x), at(z))
    }

    /// Index of the tile holding world (x, z): row-major in z, then x.
    pub fn index(&self, x: f32, z: f32) -> u32 {
        let (cx, cz) = self.cell(x, z);
        cz * self.tiles + cx
    }

    /// Number of tiles.
    pub fn count(&self) -> u32 {
        self.tiles * self.tiles
    }

    /// Slots of the rings around tile `centre` that cover the whole grid: `(2R + 1)²` with R the
    /// largest Chebyshev distance from `centre` to a tile (`shaders/cull/cull.glsl`, `ring_cell`).
    pub fn ring_slots(&self, centre: (u32, u32)) -> u32 {
        let far = |c: u32| c.max(self.tiles - 1 - c);
        let r = far(centre.0).max(far(centre.1));
        (2 * r + 1) * (2 * r + 1)
    }
}

/// Offset (dx, dz) of ring slot `slot` from the centre tile: slot 0 is the centre, ring r ≥ 1
/// holds slots `(2r − 1)² .. (2r + 1)²`, walked along its four sides. The CPU twin of
/// `ring_cell` in `shaders/cull/cull.glsl`, so nearer rings come first: near-to-far order.
pub fn ring_cell(slot: u32) -> (i32, i32) {
    if slot == 0 {
        return (0, 0);
    }
    // Ring r: the largest r with (2r − 1)² ≤ slot.
    let mut r = (((slot as f64).sqrt() + 1.0) / 2.0).floor() as i64;
    while (2 * r - 1) * (2 * r - 1) > i64::from(slot) {
        r -= 1;
    }
    while (2 * r + 1) * (2 * r + 1) <= i64::from(slot) {
        r += 1;
    }
    let p = i64::from(slot) - (2 * r - 1) * (2 * r - 1); // 0 .. 8r
    let side = p / (2 * r);
    let along = p % (2 * r);
    let (dx, dz) = match side {
        0 => (-r + along, -r),
        1 => (r, -r + along),
        2 => (r - along, r),
        _ => (-r, r - along),
    };
    (dx as i32, dz as i32)
}

/// Sort `blades` into the tiles of `grid` (a counting sort), order each tile's blades so that
/// every prefix is an even thinning of the tile (`progressive_order`), and build the tiles with
/// their padded bounds. Returns the tiles, row-major.
pub fn arrange(grid: &TileGrid, blades: &mut Vec<BladeInstance>) -> Vec<BladeTile> {
    let count = grid.count() as usize;
    let index: Vec<u32> = blades.iter().map(|b| grid.index(b.position[0], b.position[2])).collect();
    let mut starts = vec![0u32; count + 1];
    for &i in &index {
        starts[i as usize + 1] += 1;
    }
    for i in 0..count {
        starts[i + 1] += starts[i];
    }
    let mut next = starts.clone();
    let mut sorted = vec![BladeInstance::default(); blades.len()];
    for (blade, &i) in blades.iter().zip(&index) {
        sorted[next[i as usize] as usize] = *blade;
        next[i as usize] += 1;
    }
    *blades = sorted;
    (0..count)
        .map(|t| {
            let (first, end) = (starts[t], starts[t + 1]);
            progressive_order(&mut blades[first as usize..end as usize]);
            bounds(&blades[first as usize..end as usize], first)
        })
        .collect()
}

/// Bits per axis of the Morton code `progressive_order` sorts by.
const MORTON_BITS: u32 = 10;

/// Reorder `blades` (one tile's, scattered at random) so that each prefix spreads evenly over
/// the tile at every scale, for the density LOD that draws a prefix of each tile (Belyaev §2.2):
/// sort the roots along a Morton (Z-order) curve over their bounds, then take them in the
/// van der Corput order of their rank on the curve (rank = the bit-reversed index, skipping
/// ranks past the end), so the first k blades sample the curve at about even steps of n / k.
/// A random order thins evenly only on average: its prefixes' Poisson clumps and gaps showed in
/// the thinned field's 8x8-filtered difference from the whole field.
pub fn progressive_order(blades: &mut [BladeInstance]) {
    let n = blades.len();
    if n < 3 {
        return;
    }
    let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
    for b in blades.iter() {
        for (axis, &p) in [b.position[0], b.position[2]].iter().enumerate() {
            lo[axis] = lo[axis].min(p);
            hi[axis] = hi[axis].max(p);
        }
    }
    let cells = (1u32 << MORTON_BITS) as f32;
    let quantize = |p: f32, axis: usize| -> u32 {
        let unit = (p - lo[axis]) / (hi[axis] - lo[axis]).max(f32::MIN_POSITIVE);
        ((unit * cells) as u32).min((1 << MORTON_BITS) - 1)
    };
    let morton = |b: &BladeInstance| -> u32 {
        let (x, z) = (quantize(b.position[0], 0), quantize(b.position[2], 1));
        (0..MORTON_BITS).map(|i| (((x >> i) & 1) << (2 * i)) | (((z >> i) & 1) << (2 * i + 1))).sum()
    };
    let mut along: Vec<(u32, BladeInstance)> = blades.iter().map(|b| (morton(b), *b)).collect();
    along.sort_by_key(|&(key, _)| key); // stable: ties keep the scattered order
    let bits = usize::BITS - (n - 1).leading_zeros();
    let ranks = (0..1usize << bits).map(|k| k.reverse_bits() >> (usize::BITS - bits)).filter(|&r| r < n);
    for (slot, rank) in blades.iter_mut().zip(ranks) {
        *slot = along[rank].1;
    }
}

/// How far a blade reaches from its root in any pose: along each horizontal axis, and up. It
/// bends about its root but keeps its length, and its width is horizontal and at most
/// `MAX_WIDENING` times its own (the density LOD's widening).
pub fn blade_reach(blade: &BladeInstance) -> (f32, f32) {
    (blade.height + 0.5 * blade.width * MAX_WIDENING, blade.height + 0.5 * blade.width)
}

/// The tile of `blades` (starting at `first`): its box holds every blade in any pose, widened or
/// not: the box of the roots padded by `blade_reach` (never below the root).
fn bounds(blades: &[BladeInstance], first: u32) -> BladeTile {
    let mut tile = BladeTile { min: [f32::MAX; 3], first, max: [f32::MIN; 3], count: blades.len() as u32 };
    for blade in blades {
        let (across, up) = blade_reach(blade);
        for axis in 0..3 {
            let (below, above) = if axis == 1 { (0.0, up) } else { (across, across) };
            tile.min[axis] = tile.min[axis].min(blade.position[axis] - below);
            tile.max[axis] = tile.max[axis].max(blade.position[axis] + above);
        }
    }
    if blades.is_empty() {
        // An empty tile: a box no frustum holds is not needed, the count of 0 culls it.
        tile.min = [0.0; 3];
        tile.max = [0.0; 3];
    }
    tile
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn rings_cover_each_cell_once_in_order_of_distance() {
        let mut seen = std::collections::HashSet::new();
        let mut last_ring = 0;
        for slot in 0..(9 * 9) {
            let (dx, dz) = ring_cell(slot);
            let ring = dx.abs().max(dz.abs());
            assert!(ring >= last_ring, "slot {slot}: ring {ring} after {last_ring}");
            last_ring = ring;
            assert!(seen.insert((dx, dz)), "slot {slot} repeats ({dx}, {dz})");
        }
        assert_eq!(seen.len(), 81);
        assert!(seen.iter().all(|(x, z)| x.abs() <= 4 && z.abs() <= 4));
    }

    #[test]
    fn tiles_hold_contiguous_blades_with_padded_bounds() {
        let scene = Scene::generate(20_000, 3);
        let grid = scene.tile_grid;
        assert!(grid.tiles > 1);
        let mut next = 0;
        for (t, tile) in scene.tiles.iter().enumerate() {
            assert_eq!(tile.first, next, "tile {t} starts after the previous one");
            next += tile.count;
            for blade in &scene.blades[tile.first as usize..(tile.first + tile.count) as usize] {
                let [x, y, z] = blade.position;
                assert_eq!(grid.index(x, z), t as u32);
                let (across, up) = blade_reach(blade);
                assert!(across > up, "the reach across counts the widening");
                assert!(x - across >= tile.min[0] && x + across <= tile.max[0]);
                assert!(z - across >= tile.min[2] && z + across <= tile.max[2]);
                assert!(y >= tile.min[1] && y + up <= tile.max[1]);
            }
        }
        assert_eq!(next as usize, scene.blades.len());
    }

    #[test]
    fn a_tile_prefix_is_an_even_thinning() {
        // The first quarter of each tile's blades spreads over the whole tile: each quadrant of
        // the tile gets about a quarter of them.
        let scene = Scene::generate(40_000, 5);
        let grid = scene.tile_grid;
        let tile = scene.tiles[(grid.count() / 2) as usize];
        let prefix = &scene.blades[tile.first as usize..(tile.first + tile.count / 4) as usize];
        let (cx, cz) = (0.5 * (tile.min[0] + tile.max[0]), 0.5 * (tile.min[2] + tile.max[2]));
        let mut quadrants = [0usize; 4];
        for b in prefix {
            quadrants[usize::from(b.position[0] > cx) + 2 * usize::from(b.position[2] > cz)] += 1;
        }
        let expected = prefix.len() as f64 / 4.0;
        for q in quadrants {
            assert!((q as f64 - expected).abs() < 0.25 * expected, "{quadrants:?}");
        }
    }

    /// The largest deviation, in units of the expected count, of the 4x4 sub-cells of the square
    /// [0, 1)² from an even share of `blades`.
    fn worst_cell_deviation(blades: &[BladeInstance]) -> f64 {
        let mut cells = [0usize; 16];
        for b in blades {
            let (x, z) = ((b.position[0] * 4.0) as usize, (b.position[2] * 4.0) as usize);
            cells[x.min(3) + 4 * z.min(3)] += 1;
        }
        let expected = blades.len() as f64 / 16.0;
        cells.iter().map(|&c| (c as f64 - expected).abs() / expected).fold(0.0, f64::max)
    }

    #[test]
    fn progressive_order_thins_evenly_at_every_prefix_where_random_order_clumps() {
        // 2048 roots scattered at random over a unit square, as a tile's. Every prefix of 1/8,
        // 1/4 and 1/2 of them puts within 25 % of an even share in each of 16 sub-cells; in the
        // scattered order (the control) some sub-cell of some prefix strays further, as Poisson
        // counts of 16 to 64 do.
        let mut rng = crate::scene::rng::Rng::new(11);
        let scattered: Vec<BladeInstance> = (0..2048)
            .map(|_| BladeInstance { position: [rng.range(0.0, 1.0), 0.0, rng.range(0.0, 1.0)], ..Default::default() })
            .collect();
        let mut ordered = scattered.clone();
        progressive_order(&mut ordered);
        let sorted = |v: &[BladeInstance]| {
            let mut keys: Vec<[u32; 2]> =
                v.iter().map(|b| [b.position[0].to_bits(), b.position[2].to_bits()]).collect();
            keys.sort_unstable();
            keys
        };
        assert_eq!(sorted(&ordered), sorted(&scattered), "a permutation of the same blades");
        let prefixes = [256, 512, 1024];
        let worst = |v: &[BladeInstance]| prefixes.iter().map(|&k| worst_cell_deviation(&v[..k])).fold(0.0, f64::max);
        assert!(worst(&ordered) < 0.25, "progressive: {}", worst(&ordered));
        assert!(worst(&scattered) > 0.25, "scattered (control): {}", worst(&scattered));
    }
}
