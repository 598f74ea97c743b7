//! Where grass grows (issue #35 items 2 and 3): the ground's cover, a density in [0, 1] over the
//! ground, the product of two rules.
//! - `--cover PATH.png`, a covering map (Zhang Xia §5.5's covering map of model IDs, generalised
//!   to densities): red, or a greyscale map's grey, is the grass's density, 0 none and 255 full;
//!   green (a greyscale map's grey again) is the flowers' (`scene::flowers`), alpha is ignored
//!   and a palette is expanded. It is stretched over the heightmap's extent (or `--terrain-scale`'s X
//!   and Z without one) centred on the world's origin and placed as the heightmap is
//!   (`heightmap::map_coordinate`): repeated mirrored under an unbounded field, held past its
//!   edges over a bounded field's square or stored blades. Density is bilinear between texels;
//!   a 1 × 1 map is a uniform density.
//! - `--slope-limit DEG` leaves ground steeper than the limit bare, with a soft edge of
//!   `SLOPE_SOFT_DEG` across it (smoothstep of the slope's angle from `limit − 2°` to `limit + 2°`).
//!
//! A block field's cull keeps a blade only where its rank in its cell is under the cover at its
//! root (`render::ground`, `shaders/cull/cull.glsl`): the ground thins evenly and cuts no holes
//! in the cells, and the survivors are not widened (bare ground is bare, unlike the distance
//! LOD's thinning). A stored field applies it when its blades are scattered, so brute force draws
//! the same field. The terrain is tinted by it: earth where bare.

use std::path::Path;
use std::sync::Arc;

use glam::Vec2;
use image::ColorType;

use crate::error::Result;
use crate::scene::heightmap::{map_coordinate, read_png};

/// The width of the slope limit's soft edge, in degrees of slope.
pub const SLOPE_SOFT_DEG: f32 = 4.0;

/// The ground's cover rules.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cover {
    /// `--slope-limit`: the steepest slope covered, in degrees.
    pub slope_limit_deg: Option<f32>,
    /// `--cover`: the covering map.
    pub map: Option<Arc<CoverMap>>,
}

impl Cover {
    /// Whether any rule thins the grass (otherwise the cover is 1 everywhere, and the shaders
    /// compile its reads out).
    pub fn active(&self) -> bool {
        self.slope_limit_deg.is_some() || self.map.is_some()
    }

    /// The cover at world (x, z) (m) over ground of slope `slope` (dh/dx, dh/dz).
    pub fn density(&self, x: f64, z: f64, slope: Vec2) -> f32 {
        let map = self.map.as_ref().map_or(1.0, |m| m.density_at(x, z));
        map * self.slope_factor(slope)
    }

    /// The flowers' cover at world (x, z) over ground of slope `slope`: the map's green (1
    /// without a map) times the slope limit's factor.
    pub fn flower_density(&self, x: f64, z: f64, slope: Vec2) -> f32 {
        let map = self.map.as_ref().map_or(1.0, |m| m.flower_density_at(x, z));
        map * self.slope_factor(slope)
    }

    /// The most flowers the cover grows for one grass's worth anywhere: the map's largest ratio
    /// of green to red over its texels (a texel of no grass counted as one step of it, as the
    /// shaders' `flower_claimed` divides), 1 without a map; the slope limit thins both alike. A
    /// bilinear mix of texels has a ratio between theirs, so no place the grass grows exceeds it
    /// (the far field's flower tiles are baked at the share this allows, `render::far_field`).
    pub fn flower_ratio_bound(&self) -> f32 {
        self.map.as_ref().map_or(1.0, |map| {
            let ratio = |(&g, &f): (&u8, &u8)| f32::from(f) / f32::from(g.max(1));
            map.grass.iter().zip(&map.flowers).map(ratio).fold(0.0, f32::max)
        })
    }

    /// The slope limit's factor over ground of slope `slope` (1 without a limit).
    fn slope_factor(&self, slope: Vec2) -> f32 {
        self.slope_limit_deg.map_or(1.0, |limit| slope_density(limit, slope.length()))
    }
}

/// Where a map lies: its extent in x and z (m), centred on the world's origin, and whether it
/// repeats mirrored past its edges (otherwise its edge texels are held).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapPlacement {
    /// Extent along x (m).
    pub x: f64,
    /// Extent along z (m).
    pub z: f64,
    /// Repeated mirrored (an unbounded field's) or held past its edges.
    pub mirrored: bool,
}

/// A loaded covering map.
#[derive(Clone, Debug, PartialEq)]
pub struct CoverMap {
    /// Texels along x.
    pub width: u32,
    /// Texels along z.
    pub height: u32,
    /// Row-major (z then x) grass densities, 0 none to 255 full (a 16-bit map's rounded).
    pub grass: Vec<u8>,
    /// Row-major flower densities (green, or a greyscale map's grey), as `grass`.
    pub flowers: Vec<u8>,
    /// Where it lies.
    pub placement: MapPlacement,
}

impl CoverMap {
    /// Load `path` as a covering map placed at `placement`: any PNG of 1 × 1 texels or more.
    pub fn load(path: &Path, placement: MapPlacement) -> Result<Self> {
        let png = read_png(path, "--cover", 1)?;
        let grass = channel_samples(png.color, &png.bytes, 0).map_err(|why| png.bad(why))?;
        let flowers = channel_samples(png.color, &png.bytes, 1).map_err(|why| png.bad(why))?;
        Ok(Self { width: png.width, height: png.height, grass, flowers, placement })
    }

    /// The grass's density at world (x, z) (m): bilinear between the texels around it.
    pub fn density_at(&self, x: f64, z: f64) -> f32 {
        self.bilinear(&self.grass, x, z)
    }

    /// The flowers' density at world (x, z) (m), as `density_at`.
    pub fn flower_density_at(&self, x: f64, z: f64) -> f32 {
        self.bilinear(&self.flowers, x, z)
    }

    /// `plane` (`grass` or `flowers`) at world (x, z): bilinear between the texels around it.
    fn bilinear(&self, plane: &[u8], x: f64, z: f64) -> f32 {
        let p = self.placement;
        let u = map_coordinate(x, p.x, self.width, p.mirrored);
        let v = map_coordinate(z, p.z, self.height, p.mirrored);
        let (x0, z0) = (u.floor(), v.floor());
        let (fx, fz) = ((u - x0) as f32, (v - z0) as f32);
        let texel = |dx: i64, dz: i64| {
            let x = (x0 as i64 + dx).clamp(0, i64::from(self.width) - 1);
            let z = (z0 as i64 + dz).clamp(0, i64::from(self.height) - 1);
            f32::from(plane[(z * i64::from(self.width) + x) as usize]) / 255.0
        };
        let bottom = texel(0, 0) + fx * (texel(1, 0) - texel(0, 0));
        let top = texel(0, 1) + fx * (texel(1, 1) - texel(0, 1));
        bottom + fz * (top - bottom)
    }

    /// Whether the map has no grass anywhere.
    pub fn bare(&self) -> bool {
        self.grass.iter().all(|&g| g == 0)
    }
}

/// A decoded image's samples of `channel` (0 red, 1 green), as 8 bits: a greyscale map's grey
/// for either, a colour map's channel (a palette comes expanded to colour); alpha is not read.
fn channel_samples(color: ColorType, bytes: &[u8], channel: usize) -> std::result::Result<Vec<u8>, String> {
    let channels = usize::from(color.channel_count());
    let sample_bytes = usize::from(color.bytes_per_pixel()) / channels;
    if !matches!(sample_bytes, 1 | 2) || channels == 0 {
        return Err(format!("its samples ({color:?}) are not 8- or 16-bit"));
    }
    let pixel = channels * sample_bytes;
    // Grey (and grey with alpha) has one colour channel.
    let at = if channels >= 3 { channel * sample_bytes } else { 0 };
    Ok(bytes
        .chunks_exact(pixel)
        .map(|p| match sample_bytes {
            2 => ((u32::from(u16::from_ne_bytes([p[at], p[at + 1]])) * 255 + 32_767) / 65_535) as u8,
            _ => p[at],
        })
        .collect())
}

/// The slope limit's factor for ground of slope `slope` (rise over run) under a limit of
/// `limit_deg`: 1 below the soft edge, 0 above it, smoothstep across it
/// (`slope_cover` in `shaders/terrain/cover_fill.glsl`).
pub fn slope_density(limit_deg: f32, slope: f32) -> f32 {
    let angle = slope.atan().to_degrees();
    let t = ((angle - (limit_deg - 0.5 * SLOPE_SOFT_DEG)) / SLOPE_SOFT_DEG).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// Whether the stored blade `index` of a field from `seed` stands on ground of cover `density`:
/// a hash of the index against the density, so the rest of the scatter does not change.
pub fn kept(index: u32, seed: u64, density: f32) -> bool {
    if density >= 1.0 {
        return true;
    }
    let h = crate::scene::rng::mix(u64::from(index) ^ seed.rotate_left(17) ^ 0xc0ce);
    ((h >> 40) as f32 / (1u64 << 24) as f32) < density
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flower_ratio_bound_is_the_largest_green_to_red_of_the_map() {
        let placement = MapPlacement { x: 10.0, z: 10.0, mirrored: false };
        let map = |grass: Vec<u8>, flowers: Vec<u8>| Cover {
            slope_limit_deg: Some(30.0),
            map: Some(Arc::new(CoverMap { width: 2, height: 2, grass, flowers, placement })),
        };
        assert_eq!(Cover::default().flower_ratio_bound(), 1.0);
        assert_eq!(map(vec![255; 4], vec![0, 255, 51, 0]).flower_ratio_bound(), 1.0);
        assert_eq!(map(vec![255, 100, 255, 0], vec![0, 200, 0, 0]).flower_ratio_bound(), 2.0);
        // No grass where flowers grow: one step of grass, as the shaders divide.
        assert_eq!(map(vec![255, 0, 255, 255], vec![0, 3, 0, 0]).flower_ratio_bound(), 3.0);
        assert_eq!(map(vec![255; 4], vec![0; 4]).flower_ratio_bound(), 0.0);
        // Past any texel's ratio, no bilinear mix of the map exceeds it.
        let m = map(vec![255, 100, 40, 255], vec![0, 200, 30, 10]);
        let bound = m.flower_ratio_bound();
        for i in 0..=40 {
            for j in 0..=40 {
                let (x, z) = (-5.0 + 0.25 * f64::from(i), -5.0 + 0.25 * f64::from(j));
                let cover = m.map.as_ref().unwrap();
                let ratio = cover.flower_density_at(x, z) / cover.density_at(x, z).max(1.0 / 255.0);
                assert!(ratio <= bound * 1.0001, "{ratio} at ({x}, {z}) over {bound}");
            }
        }
    }

    #[test]
    fn the_slope_limit_is_soft_across_its_edge() {
        let slope = |deg: f32| deg.to_radians().tan();
        assert_eq!(slope_density(30.0, slope(20.0)), 1.0);
        assert_eq!(slope_density(30.0, slope(40.0)), 0.0);
        assert!((slope_density(30.0, slope(30.0)) - 0.5).abs() < 1e-3);
        let edge = slope_density(30.0, slope(29.0));
        assert!(edge > 0.5 && edge < 1.0, "{edge}");
        assert_eq!(Cover::default().density(0.0, 0.0, Vec2::new(10.0, 0.0)), 1.0);
        // Half the blades kept at half the density, whatever the seed.
        let share = (0..10_000).filter(|&i| kept(i, 3, 0.5)).count();
        assert!((4_700..5_300).contains(&share), "{share}");
        assert!((0..100).all(|i| kept(i, 3, 1.0)) && (0..100).all(|i| !kept(i, 3, 0.0)));
    }

    #[test]
    fn a_covering_map_is_bilinear_and_placed_like_the_heightmap() {
        // 3 × 2 texels over 100 × 50 m: (0, 51, 102) then (153, 204, 255).
        let placement = MapPlacement { x: 100.0, z: 50.0, mirrored: true };
        let map =
            CoverMap { width: 3, height: 2, grass: vec![0, 51, 102, 153, 204, 255], flowers: vec![0; 6], placement };
        let near = |a: f32, b: f32| (a - b).abs() < 1e-6;
        assert!(near(map.density_at(-50.0, -25.0), 0.0));
        assert!(near(map.density_at(50.0, 25.0), 1.0));
        assert!(near(map.density_at(-25.0, 0.0), 0.4), "{}", map.density_at(-25.0, 0.0));
        // Mirrored past the edge; held when not.
        assert!(near(map.density_at(60.0, 3.0), map.density_at(40.0, 3.0)));
        let held = CoverMap { placement: MapPlacement { mirrored: false, ..placement }, ..map.clone() };
        assert!(near(held.density_at(80.0, 30.0), 1.0));
        // A 1 × 1 map: one density everywhere.
        let uniform = CoverMap { width: 1, height: 1, grass: vec![128], flowers: vec![7], placement };
        assert!(near(uniform.density_at(1234.5, -77.0), 128.0 / 255.0));
        // With a slope limit: the product.
        let cover = Cover { slope_limit_deg: Some(30.0), map: Some(Arc::new(uniform)) };
        let half_way = 30f32.to_radians().tan();
        assert!((cover.density(0.0, 0.0, Vec2::new(half_way, 0.0)) - 0.5 * 128.0 / 255.0).abs() < 1e-3);
        // Samples: grey (for either channel), red or green of colour, 16-bit rounded.
        assert_eq!(channel_samples(ColorType::La8, &[7, 1, 9, 2], 0).unwrap(), [7, 9]);
        assert_eq!(channel_samples(ColorType::La8, &[7, 1, 9, 2], 1).unwrap(), [7, 9]);
        assert_eq!(channel_samples(ColorType::Rgba8, &[10, 20, 30, 40], 0).unwrap(), [10]);
        assert_eq!(channel_samples(ColorType::Rgba8, &[10, 20, 30, 40], 1).unwrap(), [20]);
        assert_eq!(channel_samples(ColorType::L16, &[0xff, 0xff, 0x80, 0x80], 0).unwrap(), [255, 128]);
        assert_eq!(channel_samples(ColorType::Rgb16, &[0, 0, 0xff, 0xff, 0, 0], 1).unwrap(), [255]);
        // The flowers' density is the green plane, bilinear as the grass's.
        let flowers = CoverMap { flowers: vec![255, 0, 255, 0, 255, 0], ..map.clone() };
        let as_grass = CoverMap { grass: flowers.flowers.clone(), ..map.clone() };
        for (x, z) in [(-80.0, -30.0), (10.0, 5.0), (33.0, -12.5)] {
            assert_eq!(flowers.flower_density_at(x, z), as_grass.density_at(x, z));
            assert_eq!(flowers.density_at(x, z), map.density_at(x, z));
        }
        assert_ne!(flowers.flower_density_at(10.0, 5.0), map.density_at(10.0, 5.0));
    }
}
