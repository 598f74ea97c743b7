//! A heightmap's min/max pyramid (issue #35 item 1): per block of texels the lowest and highest
//! sample, so the cull bounds a block field's cell by the map under it instead of by the map's
//! steepest slope anywhere (`field_cell_bounds` in `shaders/common/field.glsl`, through
//! `shaders/common/ground_bounds.glsl`).
//!
//! Level k ≥ 1 holds, for texel (i, j), the least and greatest 16-bit sample of the map's texels
//! i·2^k ..= (i+1)·2^k by j·2^k ..= (j+1)·2^k (one texel of overlap with the next, so the
//! continuous square [i·2^k, (i+1)·2^k]² of texel coordinates, and every bilinear point in it, is
//! bounded by it), up to a level of one texel. The drawn ground interpolates heights the map's
//! bilinear surface takes at the clipmap's vertices, so it lies within the bounds of the texels
//! around those vertices. The levels live on the GPU at 4 bytes a texel: level 1 has a quarter of
//! the map's texels and the levels above a third of that, so the pyramid adds 1.33 bytes a map
//! texel to the map's 2.
//!
//! A query (`bounds`) takes a rectangle of the world, finds its texel-coordinate range on each
//! axis (folded as the map is placed: mirrored past its edges, or held), and reads the 2 × 2
//! texels of the level whose texels are as wide as that range.

use glam::DVec2;

use crate::scene::heightmap::Heightmap;

/// Words of the GPU header: levels, the height of white (f32 bits), the map's width and height,
/// its extent in x and z (f32 bits), mirrored, then per level its width, height and first word.
pub const HEADER_WORDS: usize = 8;
/// The most levels (a 16 384-texel side has 14).
pub const MAX_LEVELS: usize = 16;

/// One level: its size in texels and its (min, max) samples, row-major.
#[derive(Clone, Debug, PartialEq)]
struct Level {
    width: u32,
    height: u32,
    bounds: Vec<(u16, u16)>,
}

/// A heightmap's min/max pyramid, levels 1 and up.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightBounds {
    levels: Vec<Level>,
    width: u32,
    height: u32,
    extent: DVec2,
    white: f64,
    mirrored: bool,
}

/// Texels of level k along an axis of `texels` map texels: enough of 2^k to cover [0, texels − 1].
fn level_side(texels: u32, k: u32) -> u32 {
    (texels.max(2) - 1).div_ceil(1 << k)
}

impl HeightBounds {
    /// Build the pyramid of `map`.
    pub fn new(map: &Heightmap) -> Self {
        let (w, h) = (map.width, map.height);
        let sample = |x: u32, z: u32| map.texels[(z.min(h - 1) * w + x.min(w - 1)) as usize];
        // Level 1 from the map: texel (i, j) over map texels 2i..=2i+2.
        let mut levels = Vec::new();
        let (lw, lh) = (level_side(w, 1), level_side(h, 1));
        let mut first = Vec::with_capacity((lw * lh) as usize);
        for j in 0..lh {
            for i in 0..lw {
                let mut b = (u16::MAX, 0u16);
                for z in 2 * j..=2 * j + 2 {
                    for x in 2 * i..=2 * i + 2 {
                        let s = sample(x, z);
                        b = (b.0.min(s), b.1.max(s));
                    }
                }
                first.push(b);
            }
        }
        levels.push(Level { width: lw, height: lh, bounds: first });
        // Each next level from the one below: texel (i, j) over its texels 2i..=2i+1 (their
        // overlaps give the next level's).
        while levels.len() < MAX_LEVELS {
            let below = levels.last().expect("a level");
            if below.width == 1 && below.height == 1 {
                break;
            }
            let (nw, nh) = (below.width.div_ceil(2), below.height.div_ceil(2));
            let mut bounds = Vec::with_capacity((nw * nh) as usize);
            for j in 0..nh {
                for i in 0..nw {
                    let mut b = (u16::MAX, 0u16);
                    for z in 2 * j..(2 * j + 2).min(below.height) {
                        for x in 2 * i..(2 * i + 2).min(below.width) {
                            let s = below.bounds[(z * below.width + x) as usize];
                            b = (b.0.min(s.0), b.1.max(s.1));
                        }
                    }
                    bounds.push(b);
                }
            }
            levels.push(Level { width: nw, height: nh, bounds });
        }
        let s = map.scale;
        Self { levels, width: w, height: h, extent: DVec2::new(s.x, s.z), white: s.y, mirrored: map.mirrored }
    }

    /// Levels held (level 1 first).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// The GPU's words (`GroundBounds`, `shaders/common/ground_bounds.glsl`): `HEADER_WORDS`, then
    /// per level of `MAX_LEVELS` its width, height and first word, then the levels, a texel a
    /// word (min in the low half, max in the high half).
    pub fn words(&self) -> Vec<u32> {
        let table = HEADER_WORDS + 3 * MAX_LEVELS;
        let texels: usize = self.levels.iter().map(|l| l.bounds.len()).sum();
        let mut words = Vec::with_capacity(table + texels);
        let f = |v: f64| (v as f32).to_bits();
        words.extend([self.levels.len() as u32, f(self.white), self.width, self.height]);
        words.extend([f(self.extent.x), f(self.extent.y), u32::from(self.mirrored), 0]);
        let mut at = table as u32;
        for k in 0..MAX_LEVELS {
            match self.levels.get(k) {
                Some(l) => {
                    words.extend([l.width, l.height, at]);
                    at += l.width * l.height;
                }
                None => words.extend([0, 0, 0]),
            }
        }
        for l in &self.levels {
            words.extend(l.bounds.iter().map(|&(lo, hi)| u32::from(lo) | (u32::from(hi) << 16)));
        }
        words
    }

    /// The lowest and highest height (m) of the map's bilinear surface over the world's rectangle
    /// `lo`..`hi` (x, z, m, relative to the world's origin): a bound, tight to a level's texel.
    pub fn bounds(&self, lo: DVec2, hi: DVec2) -> (f64, f64) {
        let (x0, x1) = axis_range(lo.x, hi.x, self.extent.x, self.width, self.mirrored);
        let (z0, z1) = axis_range(lo.y, hi.y, self.extent.y, self.height, self.mirrored);
        let span = (x1 - x0).max(z1 - z0).max(1.0);
        let k = (span.log2().ceil().max(1.0) as usize).min(self.levels.len());
        let level = &self.levels[k - 1];
        let size = f64::from(1u32 << k);
        let (i0, i1) = ((x0 / size) as u32, ((x1 / size) as u32).min(level.width - 1));
        let (j0, j1) = ((z0 / size) as u32, ((z1 / size) as u32).min(level.height - 1));
        let mut b = (u16::MAX, 0u16);
        for j in j0.min(level.height - 1)..=j1 {
            for i in i0.min(level.width - 1)..=i1 {
                let s = level.bounds[(j * level.width + i) as usize];
                b = (b.0.min(s.0), b.1.max(s.1));
            }
        }
        let metres = |s: u16| f64::from(s) / 65_535.0 * self.white;
        (metres(b.0), metres(b.1))
    }
}

/// The texel-coordinate range [a, b] ⊂ [0, texels − 1] the world's `lo`..`hi` covers on an axis
/// of a map `extent` metres wide centred on the origin, mirrored past its edges or held at them
/// (`heightmap::map_coordinate`, folded: a range across a mirror's edge covers the texels from
/// that edge to the farther of its two ends).
pub fn axis_range(lo: f64, hi: f64, extent: f64, texels: u32, mirrored: bool) -> (f64, f64) {
    let scale = f64::from(texels.max(2) - 1);
    let (u0, u1) = (lo / extent + 0.5, hi / extent + 0.5);
    let (a, b) = if !mirrored {
        (u0.clamp(0.0, 1.0), u1.clamp(0.0, 1.0))
    } else if u1 - u0 >= 1.0 {
        (0.0, 1.0)
    } else {
        let a = u0.rem_euclid(2.0);
        let b = a + (u1 - u0);
        if b <= 1.0 {
            (a, b)
        } else if a >= 1.0 && b <= 2.0 {
            (2.0 - b, 2.0 - a)
        } else if a < 1.0 {
            // Across the mirror at u = 1: from the nearer end to the edge.
            ((a).min(2.0 - b), 1.0)
        } else {
            // Across u = 2 (the edge at u = 0 of the next copy).
            (0.0, (2.0 - a).max(b - 2.0))
        }
    };
    (a * scale, b * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::heightmap::TerrainScale;

    /// A map of pseudo-random texels with a spike.
    fn map(width: u32, height: u32, mirrored: bool) -> Heightmap {
        let mut state = 12_345u32;
        let texels = (0..width * height)
            .map(|i| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                if i == width * height / 3 {
                    65_535
                } else {
                    (state >> 20) as u16 * 4
                }
            })
            .collect();
        let scale = TerrainScale { x: 100.0, y: 20.0, z: 60.0 };
        Heightmap { width, height, texels, bits: 16, scale, mirrored }
    }

    #[test]
    fn every_bilinear_point_of_a_rectangle_lies_within_its_bounds() {
        for (w, h, mirrored) in [(37, 23, true), (37, 23, false), (64, 65, true), (2, 2, true)] {
            let map = map(w, h, mirrored);
            let pyramid = HeightBounds::new(&map);
            let mut state = 99u32;
            let mut next = || {
                state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                f64::from(state >> 8) / f64::from(1u32 << 24)
            };
            let mut tighter = 0;
            for _ in 0..400 {
                let lo = DVec2::new(next() * 500.0 - 250.0, next() * 300.0 - 150.0);
                let hi = lo + DVec2::new(next() * 12.0, next() * 12.0);
                let (min, max) = pyramid.bounds(lo, hi);
                let (mut seen_min, mut seen_max) = (f64::MAX, f64::MIN);
                for s in 0..=24 {
                    for t in 0..=24 {
                        let p = lo + (hi - lo) * DVec2::new(f64::from(s), f64::from(t)) / 24.0;
                        let z = map.height_at(p.x, p.y);
                        assert!(z >= min - 1e-9 && z <= max + 1e-9, "{w}x{h}: {z} outside {min}..{max} at {p}");
                        (seen_min, seen_max) = (seen_min.min(z), seen_max.max(z));
                    }
                }
                tighter += usize::from(max - min < 0.5 * map.scale.y);
                assert!(seen_min <= seen_max);
            }
            // Small rectangles get bounds much tighter than the whole map's (the spike's 20 m).
            if w > 2 {
                assert!(tighter > 300, "{w}x{h}: only {tighter} of 400 tight");
            }
        }
    }

    #[test]
    fn the_levels_halve_to_one_texel_and_the_words_hold_them() {
        let pyramid = HeightBounds::new(&map(37, 23, true));
        let sides: Vec<(u32, u32)> = pyramid.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sides, [(18, 11), (9, 6), (5, 3), (3, 2), (2, 1), (1, 1)]);
        // The top holds the whole map's range: the spike and the lowest sample.
        let top = pyramid.levels.last().expect("top").bounds[0];
        let samples = &map(37, 23, true).texels;
        assert_eq!(top, (*samples.iter().min().expect("min"), 65_535));
        let words = pyramid.words();
        assert_eq!(words[0] as usize, pyramid.levels());
        let total: u32 = sides.iter().map(|(w, h)| w * h).sum();
        assert_eq!(words.len(), HEADER_WORDS + 3 * MAX_LEVELS + total as usize);
        // Level 2's first word is after level 1's texels.
        assert_eq!(words[HEADER_WORDS + 3 + 2], (HEADER_WORDS + 3 * MAX_LEVELS) as u32 + 18 * 11);
    }

    #[test]
    fn a_range_across_a_mirror_folds_onto_its_edge() {
        // A 100 m map of 11 texels: u = x / 100 + 0.5.
        assert_eq!(axis_range(-10.0, 10.0, 100.0, 11, true), (4.0, 6.0));
        // Across x = 50 (u = 1): from the nearer end to the edge.
        let (a, b) = axis_range(45.0, 52.0, 100.0, 11, true);
        assert!((a - 9.5).abs() < 1e-9 && b == 10.0, "{a}..{b}");
        // Across x = -50 (u = 0, reached from the copy below).
        let (a, b) = axis_range(-53.0, -48.0, 100.0, 11, true);
        assert!(a == 0.0 && (b - 0.3).abs() < 1e-9, "{a}..{b}");
        // Held: clamped.
        assert_eq!(axis_range(45.0, 80.0, 100.0, 11, false), (9.5, 10.0));
        // Wider than a copy: everything.
        assert_eq!(axis_range(0.0, 120.0, 100.0, 11, true), (0.0, 10.0));
    }
}
