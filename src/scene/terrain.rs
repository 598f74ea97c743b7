//! Procedural terrain: a seeded height field of gentle hills on a square grid, drawn as a
//! triangle mesh expanded in the vertex shader from the height buffer.

use crate::scene::rng::mix;

/// Edge length of one terrain cell in metres.
pub const CELL_SIZE: f32 = 0.5;
/// Largest grid (cells per side) meadow builds; larger fields use coarser cells.
pub const MAX_CELLS: u32 = 1024;

/// A square height field centred on the origin. Heights are stored at grid vertices; each cell is
/// split into the triangles (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), in the shader too, so
/// `height_at` is exactly the rendered surface.
#[derive(Clone, Debug)]
pub struct Terrain {
    /// Side length in metres.
    pub size: f32,
    /// Cells per side.
    pub cells: u32,
    /// `(cells + 1)²` heights, row-major in z then x.
    pub heights: Vec<f32>,
}

impl Terrain {
    /// Build the height field for a field of side `size` metres.
    pub fn generate(size: f32, seed: u64) -> Self {
        let cells = Self::cells_for(size);
        let n = cells + 1;
        let step = size / cells as f32;
        let origin = -0.5 * size;
        let mut heights = Vec::with_capacity((n * n) as usize);
        for z in 0..n {
            for x in 0..n {
                heights.push(hills(origin + x as f32 * step, origin + z as f32 * step, seed));
            }
        }
        Self { size, cells, heights }
    }

    /// The height field for a field of side `size` metres on the heightmap `map` (over its
    /// centre, sampled at the grid's vertices in f64).
    pub fn from_heightmap(size: f32, map: &crate::scene::heightmap::Heightmap) -> Self {
        let cells = Self::cells_for(size);
        let n = cells + 1;
        let step = f64::from(size) / f64::from(cells);
        let origin = -0.5 * f64::from(size);
        let heights = (0..n)
            .flat_map(|z| (0..n).map(move |x| (x, z)))
            .map(|(x, z)| map.height_at(origin + f64::from(x) * step, origin + f64::from(z) * step) as f32)
            .collect();
        Self { size, cells, heights }
    }

    /// Cells per side for a field of side `size` metres.
    pub fn cells_for(size: f32) -> u32 {
        ((size / CELL_SIZE).ceil() as u32).clamp(1, MAX_CELLS)
    }

    /// World x (= z) of grid line 0.
    pub fn origin(&self) -> f32 {
        -0.5 * self.size
    }

    /// Cell edge in metres.
    pub fn cell_size(&self) -> f32 {
        self.size / self.cells as f32
    }

    fn grid(&self, x: u32, z: u32) -> f32 {
        self.heights[(z * (self.cells + 1) + x) as usize]
    }

    /// The heights at the corners of the cell under world (x, z) (h00, h10, h01, h11, clamped to
    /// the field) and the point's position inside it, in [0, 1]².
    fn cell_at(&self, x: f32, z: f32) -> ([f32; 4], f32, f32) {
        let step = self.cell_size();
        let gx = ((x - self.origin()) / step).clamp(0.0, self.cells as f32);
        let gz = ((z - self.origin()) / step).clamp(0.0, self.cells as f32);
        let cx = (gx.floor() as u32).min(self.cells - 1);
        let cz = (gz.floor() as u32).min(self.cells - 1);
        let corners = [self.grid(cx, cz), self.grid(cx + 1, cz), self.grid(cx, cz + 1), self.grid(cx + 1, cz + 1)];
        (corners, gx - cx as f32, gz - cz as f32)
    }

    /// Height of the rendered surface at world (x, z), clamped to the field.
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        let ([h00, h10, h01, h11], fx, fz) = self.cell_at(x, z);
        if fx >= fz {
            h00 + fx * (h10 - h00) + fz * (h11 - h10)
        } else {
            h00 + fz * (h01 - h00) + fx * (h11 - h01)
        }
    }

    /// Surface normal at world (x, z): the gradient of the bilinear patch through the heights of
    /// the cell the point lies in (`grid_terrain_normal` in shaders/terrain/terrain.glsl, which the
    /// blades' Fresnel term uses).
    pub fn normal_at(&self, x: f32, z: f32) -> glam::Vec3 {
        let ([h00, h10, h01, h11], fx, fz) = self.cell_at(x, z);
        let step = self.cell_size();
        let dx = h10 - h00 + fz * ((h11 - h01) - (h10 - h00));
        let dz = h01 - h00 + fx * ((h11 - h10) - (h01 - h00));
        glam::Vec3::new(-dx, step, -dz).normalize()
    }

    /// The steepest rise between neighbouring vertices along x or z, per metre: each triangle of
    /// the mesh has one edge along x and one along z, so its slope is at most √2 times this
    /// (`render::occlusion`).
    pub fn slope_bound(&self) -> f32 {
        let n = self.cells + 1;
        let mut rise = 0.0f32;
        for z in 0..n {
            for x in 0..n {
                let h = self.grid(x, z);
                if x + 1 < n {
                    rise = rise.max((self.grid(x + 1, z) - h).abs());
                }
                if z + 1 < n {
                    rise = rise.max((self.grid(x, z + 1) - h).abs());
                }
            }
        }
        rise / self.cell_size()
    }

    /// Number of triangles of the mesh.
    pub fn triangles(&self) -> u64 {
        2 * u64::from(self.cells) * u64::from(self.cells)
    }
}

/// Gentle hills: three octaves of seeded value noise, wavelengths 24, 12 and 6 m, about ±1.5 m.
fn hills(x: f32, z: f32, seed: u64) -> f32 {
    let mut height = 0.0;
    let mut amplitude = 1.2;
    let mut wavelength = 24.0;
    for octave in 0..3u64 {
        height += amplitude * value_noise(x / wavelength, z / wavelength, seed.wrapping_add(octave * 0x51ed));
        amplitude *= 0.4;
        wavelength *= 0.5;
    }
    height
}

/// Smoothly interpolated lattice noise in [-1, 1].
fn value_noise(x: f32, z: f32, seed: u64) -> f32 {
    let (ix, iz) = (x.floor(), z.floor());
    let (fx, fz) = (x - ix, z - iz);
    let lattice = |dx: i64, dz: i64| -> f32 {
        let key = (ix as i64 + dx) as u64 ^ ((iz as i64 + dz) as u64).rotate_left(32) ^ mix(seed);
        (mix(key) >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    };
    let smooth = |t: f32| t * t * (3.0 - 2.0 * t);
    let (sx, sz) = (smooth(fx), smooth(fz));
    let a = lattice(0, 0) + sx * (lattice(1, 0) - lattice(0, 0));
    let b = lattice(0, 1) + sx * (lattice(1, 1) - lattice(0, 1));
    a + sz * (b - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_matches_grid_at_vertices_and_is_continuous() {
        let t = Terrain::generate(20.0, 3);
        let step = t.cell_size();
        for (x, z) in [(0u32, 0u32), (3, 7), (t.cells, t.cells)] {
            let h = t.height_at(t.origin() + x as f32 * step, t.origin() + z as f32 * step);
            assert!((h - t.grid(x, z)).abs() < 1e-4);
        }
        // Across the diagonal and cell edges the surface does not jump.
        let (x0, z0) = (t.origin() + 5.5 * step, t.origin() + 5.5 * step);
        let e = 1e-3;
        assert!((t.height_at(x0 + e, z0) - t.height_at(x0, z0 + e)).abs() < 1e-2);
        assert!(
            (t.height_at(t.origin() + 2.0 * step - e, z0) - t.height_at(t.origin() + 2.0 * step + e, z0)).abs() < 1e-2
        );
    }

    #[test]
    fn the_slope_bound_is_the_steepest_rise_along_an_axis() {
        // A ramp rising 0.3 m a metre along x, with one vertex 0.5 m higher than the ramp there
        // (its neighbours along z then rise 0.5 m over a 1 m cell).
        let cells = 4;
        let mut heights: Vec<f32> = (0..=cells).flat_map(|_| (0..=cells).map(|x| 0.3 * x as f32)).collect();
        let flat = Terrain { size: cells as f32, cells, heights: heights.clone() };
        assert!((flat.slope_bound() - 0.3).abs() < 1e-6, "{}", flat.slope_bound());
        heights[2 * (cells as usize + 1) + 2] += 0.5;
        let bumped = Terrain { size: cells as f32, cells, heights };
        assert!((bumped.slope_bound() - 0.8).abs() < 1e-6, "{}", bumped.slope_bound());
    }

    #[test]
    fn hills_are_gentle() {
        let t = Terrain::generate(60.0, 11);
        let max = t.heights.iter().fold(f32::MIN, |m, h| m.max(*h));
        let min = t.heights.iter().fold(f32::MAX, |m, h| m.min(*h));
        assert!(max - min > 0.3 && max - min < 4.0, "relief {}", max - min);
        let step = t.cell_size();
        for z in 0..t.cells {
            for x in 0..t.cells {
                assert!((t.grid(x + 1, z) - t.grid(x, z)).abs() / step < 0.6, "slope too steep");
            }
        }
    }
}
