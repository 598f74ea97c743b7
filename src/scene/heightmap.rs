//! A heightmap (issue #35 item 1): an 8- or 16-bit greyscale PNG stretched over `X × Z` metres
//! centred on the world's origin, black at 0 m and white `Y` metres up (`--heightmap PATH.png
//! --terrain-scale X,Y,Z`). Heights are bilinear between texels, whose centres lie on a lattice
//! from (−X/2, −Z/2) to (X/2, Z/2), and the map repeats mirrored past its edges: the ground is
//! continuous everywhere (no crack at a mirror line) and its normal creases there (the slope
//! flips sign across the line). The mirrored period is 2X × 2Z, which must divide the world's
//! period (`field::WORLD_PERIOD`) so that a view a period away draws the same ground.
//!
//! Loading refuses what is not a greyscale PNG of at least 2 × 2 texels in one line, before
//! allocating for the size its header claims: a missing path, a directory or a FIFO, a file that
//! is not a PNG or is cut short, a header over `MAX_SIDE` texels a side, a colour image (palette
//! images are expanded, and a palette of greys is grey).

use std::io::BufReader;
use std::path::Path;

use image::codecs::png::PngDecoder;
use image::{ColorType, ImageDecoder};

use crate::error::{quoted, Error, Result};
use crate::scene::field::WORLD_PERIOD;

/// The longest side a heightmap may have (texels): the image dimension every Vulkan device
/// supports for a 2-D image is 4 096, lavapipe's 16 384.
pub const MAX_SIDE: u32 = 16_384;

/// `--terrain-scale X,Y,Z`: the map's extent in x and z (metres) and the height of white above
/// black (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerrainScale {
    /// Extent along x (m).
    pub x: f64,
    /// Height of white above black (m).
    pub y: f64,
    /// Extent along z (m).
    pub z: f64,
}

impl TerrainScale {
    /// Refuse an extent whose mirrored period (twice the extent) does not divide the world's.
    pub fn check_period(&self) -> Result<()> {
        let period = f64::from(WORLD_PERIOD);
        for (axis, extent) in [("X", self.x), ("Z", self.z)] {
            let repeats = period / (2.0 * extent);
            if (repeats - repeats.round()).abs() > 1e-9 || repeats < 1.0 {
                return Err(Error::bad_input(format!(
                    "--terrain-scale {axis} = {extent} m: the map repeats mirrored every {} m, which must divide the world's \
                     period of {period} m (an extent that divides {} m)",
                    2.0 * extent,
                    period / 2.0
                )));
            }
        }
        Ok(())
    }
}

/// The scale without `--terrain-scale`: 1 km a side (its mirrored period divides the world's),
/// white 50 m up.
pub const DEFAULT_SCALE: TerrainScale = TerrainScale { x: 1000.0, y: 50.0, z: 1000.0 };

/// A loaded heightmap.
#[derive(Clone, Debug, PartialEq)]
pub struct Heightmap {
    /// Texels along x.
    pub width: u32,
    /// Texels along z.
    pub height: u32,
    /// Row-major (z then x) heights, 0 black to 65 535 white (an 8-bit map's times 257).
    pub texels: Vec<u16>,
    /// Its bits per sample in the file (8 or 16).
    pub bits: u32,
    /// Where it lies.
    pub scale: TerrainScale,
    /// Past its edges: repeated mirrored (an unbounded field's, a stored field's), or its edge
    /// texels held (a bounded field's map covers the field's square).
    pub mirrored: bool,
}

impl Heightmap {
    /// Load `path` as a heightmap of `scale`.
    pub fn load(path: &Path, scale: TerrainScale) -> Result<Self> {
        let png = read_png(path, "--heightmap", 2)?;
        let texels = grey_texels(png.color, &png.bytes).map_err(|why| png.bad(why))?;
        let bits = if png.color.bytes_per_pixel() / png.color.channel_count() == 2 { 16 } else { 8 };
        Ok(Self { width: png.width, height: png.height, texels, bits, scale, mirrored: true })
    }

    /// A map of `relief` over `extent` × `extent` metres centred on the world's origin, a texel
    /// every `spacing` metres (so `extent / spacing + 1` a side), black at the lowest height
    /// sampled and white at the highest: the procedural relief exported as a heightmap (issue
    /// #35's comparison of the two grounds; `examples/landscape_maps.rs` writes it as a PNG).
    /// Its ground lies `lowest` below the relief's, where `(map, lowest)` is returned.
    pub fn from_relief(relief: &crate::scene::field::Relief, extent: f64, spacing: f64) -> (Self, f64) {
        let side = (extent / spacing).round() as u32 + 1;
        let heights = relief.heights_on_lattice(-0.5 * extent, spacing, side);
        let (low, high) = heights.iter().fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        let range = (high - low).max(1e-6);
        let texels = heights.iter().map(|h| ((h - low) / range * 65_535.0).round() as u16).collect();
        let scale = TerrainScale { x: extent, y: range, z: extent };
        (Self { width: side, height: side, texels, bits: 16, scale, mirrored: true }, low)
    }

    /// The map's texel (clamped to the map) as a height in metres.
    pub fn texel_height(&self, x: i64, z: i64) -> f64 {
        let (x, z) = (x.clamp(0, i64::from(self.width) - 1), z.clamp(0, i64::from(self.height) - 1));
        f64::from(self.texels[(z * i64::from(self.width) + x) as usize]) / 65_535.0 * self.scale.y
    }

    /// Where world (x, z) falls on the map, in texels, mirrored past its edges (or held at them):
    /// the map's texel lattice spans [0, width − 1] × [0, height − 1] over the extent.
    pub fn texel_at(&self, x: f64, z: f64) -> (f64, f64) {
        (
            map_coordinate(x, self.scale.x, self.width, self.mirrored),
            map_coordinate(z, self.scale.z, self.height, self.mirrored),
        )
    }

    /// The ground's height at world (x, z) (m): bilinear between the texels around it.
    pub fn height_at(&self, x: f64, z: f64) -> f64 {
        let (u, v) = self.texel_at(x, z);
        let (x0, z0) = (u.floor(), v.floor());
        let (fx, fz) = (u - x0, v - z0);
        let (x0, z0) = (x0 as i64, z0 as i64);
        let h = |dx, dz| self.texel_height(x0 + dx, z0 + dz);
        let bottom = h(0, 0) + fx * (h(1, 0) - h(0, 0));
        let top = h(0, 1) + fx * (h(1, 1) - h(0, 1));
        bottom + fz * (top - bottom)
    }

    /// The steepest slope of the bilinear surface: the largest rise between neighbouring texels
    /// over their spacing, along x and z together.
    pub fn slope_bound(&self) -> f64 {
        let (dx, dz) = (self.scale.x / f64::from(self.width - 1), self.scale.z / f64::from(self.height - 1));
        let (mut sx, mut sz) = (0.0f64, 0.0f64);
        for z in 0..i64::from(self.height) {
            for x in 0..i64::from(self.width) {
                let h = self.texel_height(x, z);
                sx = sx.max((self.texel_height(x + 1, z) - h).abs() / dx);
                sz = sz.max((self.texel_height(x, z + 1) - h).abs() / dz);
            }
        }
        sx.hypot(sz)
    }
}

/// Where `world` (m from the world's origin along an axis) falls on a map of `texels` along
/// `extent` metres centred on the origin, in texels: its lattice spans [0, texels − 1], mirrored
/// past its edges (or held at them). The heightmap and the covering map (`scene::cover`) are
/// placed so; `shaders/terrain/map_coordinate.glsl` is the same on the GPU.
pub fn map_coordinate(world: f64, extent: f64, texels: u32, mirrored: bool) -> f64 {
    let u = world / extent + 0.5;
    let u = match mirrored {
        true => {
            let u = u.rem_euclid(2.0);
            if u > 1.0 {
                2.0 - u
            } else {
                u
            }
        }
        false => u.clamp(0.0, 1.0),
    };
    u * f64::from(texels.max(1) - 1)
}

/// A PNG map's decoded samples (`read_png`) and how to refuse them.
pub(crate) struct PngMap {
    pub width: u32,
    pub height: u32,
    pub color: ColorType,
    pub bytes: Vec<u8>,
    /// `--flag 'path': ` for a refusal's line.
    prefix: String,
}

impl PngMap {
    /// A refusal of this map for `why`, bad input.
    pub fn bad(&self, why: String) -> Error {
        Error::bad_input(format!("{}{why}", self.prefix))
    }
}

/// Read `path`, given as `flag`, as a PNG of at least `min_side` texels a side and at most
/// `MAX_SIDE`, refusing in one line before allocating for the size its header claims: a missing
/// path, a directory or a FIFO, a file that is not a PNG or is cut short.
pub(crate) fn read_png(path: &Path, flag: &str, min_side: u32) -> Result<PngMap> {
    let prefix = format!("{flag} '{}': ", quoted(&path.to_string_lossy()));
    let bad = |why: String| Error::bad_input(format!("{prefix}{why}"));
    // Before opening: a FIFO would block the open, a directory read as garbage.
    let meta = std::fs::metadata(path).map_err(|e| bad(format!("cannot read it ({e})")))?;
    if !meta.is_file() {
        return Err(bad("not a file".into()));
    }
    let file = std::fs::File::open(path).map_err(|e| bad(format!("cannot open it ({e})")))?;
    let decoder = PngDecoder::new(BufReader::new(file)).map_err(|e| bad(format!("not a PNG image ({e})")))?;
    let (width, height) = decoder.dimensions();
    if width < min_side || height < min_side {
        return Err(bad(format!("{width} × {height} texels: the map has {min_side} × {min_side} at least")));
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(bad(format!("{width} × {height} texels: at most {MAX_SIDE} a side")));
    }
    let color = decoder.color_type();
    let mut bytes = vec![0u8; decoder.total_bytes() as usize];
    decoder.read_image(&mut bytes).map_err(|e| bad(format!("cannot decode it ({e})")))?;
    Ok(PngMap { width, height, color, bytes, prefix })
}

/// A decoded image's samples as heights: its grey (an alpha channel is ignored), or, for colour
/// (palette images come expanded), its red where every pixel is grey; refused otherwise.
fn grey_texels(color: ColorType, bytes: &[u8]) -> std::result::Result<Vec<u16>, String> {
    let channels = usize::from(color.channel_count());
    let wide = usize::from(color.bytes_per_pixel()) / channels == 2;
    let samples: Vec<u16> = match wide {
        true => bytes.chunks_exact(2).map(|b| u16::from_ne_bytes([b[0], b[1]])).collect(),
        false => bytes.iter().map(|&b| u16::from(b) * 257).collect(),
    };
    let grey = matches!(color, ColorType::L8 | ColorType::L16 | ColorType::La8 | ColorType::La16);
    let texels: Vec<&[u16]> = samples.chunks_exact(channels).collect();
    if !grey {
        if !matches!(color, ColorType::Rgb8 | ColorType::Rgba8 | ColorType::Rgb16 | ColorType::Rgba16) {
            return Err(format!("its samples ({color:?}) are not a greyscale image"));
        }
        if let Some(at) = texels.iter().position(|p| p[0] != p[1] || p[1] != p[2]) {
            return Err(format!("a colour image (texel {at} is not grey): give a greyscale PNG"));
        }
    }
    Ok(texels.iter().map(|p| p[0]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(width: u32, height: u32, texels: Vec<u16>) -> Heightmap {
        Heightmap {
            width,
            height,
            texels,
            bits: 16,
            scale: TerrainScale { x: 100.0, y: 10.0, z: 50.0 },
            mirrored: true,
        }
    }

    #[test]
    fn heights_are_bilinear_between_texels_and_mirrored_past_the_edges() {
        // 3 × 2 texels: (0, 1, 2) then (3, 4, 5) tenths of white; x spans 100 m, z 50 m.
        let hm = map(3, 2, [0, 1, 2, 3, 4, 5].map(|t| t * 6553).to_vec());
        let h = |x, z| hm.height_at(x, z);
        let texel = |t: f64| t * 6553.0 / 65_535.0 * 10.0;
        assert!((h(-50.0, -25.0) - texel(0.0)).abs() < 1e-9);
        assert!((h(0.0, -25.0) - texel(1.0)).abs() < 1e-9);
        assert!((h(50.0, 25.0) - texel(5.0)).abs() < 1e-9);
        // Half-way between four texels: their mean.
        assert!((h(-25.0, 0.0) - texel(2.0)).abs() < 1e-9);
        // Mirrored: 10 m past the +x edge is 10 m inside it, and the period is 200 m.
        assert!((h(60.0, 3.0) - h(40.0, 3.0)).abs() < 1e-12);
        assert!((h(-60.0, 3.0) - h(-40.0, 3.0)).abs() < 1e-12);
        assert!((h(37.0, 11.0) - h(237.0, 111.0)).abs() < 1e-12);
        // Continuous across the mirror line.
        assert!((h(50.0 - 1e-7, 7.0) - h(50.0 + 1e-7, 7.0)).abs() < 1e-6);
        assert!(hm.slope_bound() > 0.0);
    }

    #[test]
    fn a_relief_exported_holds_its_heights_at_the_texels() {
        let relief = crate::scene::field::Relief::generate(5);
        let (map, low) = Heightmap::from_relief(&relief, 100.0, 0.5);
        assert_eq!((map.width, map.height), (201, 201));
        for (x, z) in [(0u32, 0u32), (200, 200), (37, 151), (100, 100)] {
            let world = (-50.0 + f64::from(x) * 0.5, -50.0 + f64::from(z) * 0.5);
            let exported = map.height_at(world.0, world.1) + low;
            // 16-bit steps of a few metres' range: well under a millimetre.
            assert!((exported - relief.height(world.0, world.1)).abs() < 1e-4, "texel ({x}, {z})");
        }
    }

    #[test]
    fn a_mirrored_period_must_divide_the_worlds() {
        assert!(TerrainScale { x: 1000.0, y: 50.0, z: 2500.0 }.check_period().is_ok());
        for bad in [3000.0, 7.0, 20_000.0] {
            let error = TerrainScale { x: bad, y: 50.0, z: 1000.0 }.check_period().unwrap_err().to_string();
            assert!(error.contains("divide"), "{error}");
        }
    }

    #[test]
    fn grey_and_colour_samples() {
        assert_eq!(grey_texels(ColorType::L8, &[0, 255]).unwrap(), [0, 65_535]);
        assert_eq!(grey_texels(ColorType::La8, &[7, 1, 9, 2]).unwrap(), [7 * 257, 9 * 257]);
        // A palette of greys, expanded: accepted; a colour texel: refused.
        assert_eq!(grey_texels(ColorType::Rgb8, &[5, 5, 5, 6, 6, 6]).unwrap(), [5 * 257, 6 * 257]);
        assert!(grey_texels(ColorType::Rgb8, &[5, 5, 5, 6, 7, 6]).unwrap_err().contains("colour"));
    }
}
