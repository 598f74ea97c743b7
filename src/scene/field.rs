//! Camera-following grass blocks (Belyaev §2.1): a field of any size, or unbounded, drawn as a
//! grid of cells around the camera, each cell a variation of one stored block of blades (rotated
//! and mirrored by a hash of its integer cell coordinates), set on a relief that can be evaluated
//! anywhere. Everything the GPU sees is relative to an origin snapped to the camera's cell, so
//! precision does not depend on how far the camera is from the world's origin.

use std::f32::consts::TAU;
use std::f64::consts::TAU as TAU64;

use glam::{DVec2, Vec2, Vec4};

use crate::scene::blades::{self, BladeInstance};
use crate::scene::rng::Rng;

/// Edge of a block in metres (a multiple of the default 1 m force cluster).
pub const BLOCK_SIZE: f32 = 4.0;
/// Most blades a block holds: the visible list packs a blade of its block in 16 bits.
pub const MAX_BLOCK_BLADES: u32 = 1 << 16;
/// Sine waves of the relief.
pub const WAVES: usize = 8;
/// The world repeats every this many metres in x and z: the relief's waves have whole periods in
/// it and the blocks' variations repeat (`shaders/common/field.glsl`, `cell_hash`). A field far from
/// the origin is then the same field, which is how the tests see that precision holds there. It
/// is twice the longest view distance (10 km), so no repeat shows inside a view.
pub const WORLD_PERIOD: f32 = 20_000.0;
/// The lattice the gentle relief's wave numbers were drawn on when the world repeated every
/// kilometre: they are whole there, and scaled to `WORLD_PERIOD` the default relief is the one it
/// always was (the same f32 waves).
const GENTLE_PERIOD: f32 = 1000.0;
/// Cells in a world period (the shaders' `PERIOD_CELLS`; `render::field_gpu` asserts they agree).
pub const PERIOD_CELLS: i32 = (WORLD_PERIOD / BLOCK_SIZE) as i32;

/// The highest density a block holds (`MAX_BLOCK_BLADES` in `BLOCK_SIZE`²).
pub fn max_density() -> f32 {
    MAX_BLOCK_BLADES as f32 / (BLOCK_SIZE * BLOCK_SIZE)
}

/// `--relief`: which relief a block field sits on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ReliefKind {
    /// Gentle hills like the stored terrain's (about ±1.5 m, wavelengths 60 to 6 m).
    #[default]
    Gentle,
    /// Hills hundreds of metres long (wavelengths 800 to 220 m, up to about ±50 m) under the
    /// gentle relief's four longest waves: a landscape to look across.
    Hills,
}

/// The hills relief's waves: wavelength (m) and amplitude (m), longest first.
const HILLS: [(f32, f32); WAVES] =
    [(800.0, 24.0), (520.0, 14.0), (340.0, 8.0), (220.0, 4.5), (60.0, 0.6), (43.2, 0.43), (31.1, 0.31), (22.4, 0.22)];

/// `--field SIZE|infinite --density D`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSpec {
    /// Side of the square field in metres, centred on the origin; `None`: unbounded.
    pub size: Option<f32>,
    /// Blades per square metre.
    pub density: f32,
}

impl FieldSpec {
    /// Blades of the stored block at this density.
    pub fn block_blades(&self) -> u64 {
        (f64::from(self.density) * f64::from(BLOCK_SIZE * BLOCK_SIZE)).round().max(1.0) as u64
    }

    /// Cells per side of a bounded field (`None`: unbounded).
    pub fn cells(&self) -> Option<u32> {
        self.size.map(|s| (s / BLOCK_SIZE).ceil().max(1.0) as u32)
    }
}

/// The relief under a block field: a sum of seeded sine waves, h(p) = Σ a_k sin(u_k · p + φ_k).
/// Evaluated relative to an origin O without losing precision far away: the GPU gets
/// sin(u_k · O + φ_k) and cos(u_k · O + φ_k), computed here in f64, and adds u_k · (p − O).
#[derive(Clone, Debug, PartialEq)]
pub struct Relief {
    /// Per wave: direction × 2π / wavelength (x, z) and amplitude (w = phase φ_k).
    pub waves: [Vec4; WAVES],
    /// Per wave: its whole periods in `WORLD_PERIOD` along x and z (the exact wave vector is
    /// 2π (m, n) / WORLD_PERIOD; `waves` holds it rounded to f32).
    pub cycles: [(i32, i32); WAVES],
}

impl Relief {
    /// Gentle hills like the stored terrain's (about ±1.5 m, wavelengths 60 to 6 m).
    pub fn generate(seed: u64) -> Self {
        Self::of_kind(ReliefKind::Gentle, seed)
    }

    /// The relief of `kind` from `seed`: each wave's direction and phase drawn in turn, its wave
    /// numbers the whole numbers of periods nearest the wavelength asked (in `GENTLE_PERIOD` for
    /// the gentle relief, scaled to `WORLD_PERIOD`; in `WORLD_PERIOD` for the hills).
    pub fn of_kind(kind: ReliefKind, seed: u64) -> Self {
        let mut rng = Rng::new(seed ^ 0x7e11ef);
        let mut waves = [Vec4::ZERO; WAVES];
        let mut cycles = [(0, 0); WAVES];
        let (mut wavelength, mut amplitude) = (60.0f32, 0.6f32);
        let lattice = match kind {
            ReliefKind::Gentle => GENTLE_PERIOD,
            ReliefKind::Hills => WORLD_PERIOD,
        };
        let scale = (WORLD_PERIOD / lattice) as i32;
        for (i, (wave, cycle)) in waves.iter_mut().zip(&mut cycles).enumerate() {
            if kind == ReliefKind::Hills {
                (wavelength, amplitude) = HILLS[i];
            }
            let angle = rng.range(0.0, TAU);
            let cycles = lattice / wavelength;
            let (m, n) = ((angle.cos() * cycles).round(), (angle.sin() * cycles).round());
            let (m, n) = if m == 0.0 && n == 0.0 { (1.0, 0.0) } else { (m, n) };
            let k = TAU / lattice;
            *wave = Vec4::new(m * k, n * k, amplitude, rng.range(0.0, TAU));
            *cycle = (m as i32 * scale, n as i32 * scale);
            wavelength *= 0.72;
            amplitude *= 0.72;
        }
        Self { waves, cycles }
    }

    /// Phase of wave `k` at world (x, z), exact in f64 from its whole periods, in [0, 2π).
    fn phase(&self, k: usize, x: f64, z: f64) -> f64 {
        let (m, n) = self.cycles[k];
        let period = f64::from(WORLD_PERIOD);
        // Whole periods of the world drop out before the products grow.
        let (x, z) = (x.rem_euclid(period), z.rem_euclid(period));
        (TAU64 * (f64::from(m) * x + f64::from(n) * z) / period + f64::from(self.waves[k].w)).rem_euclid(TAU64)
    }

    /// Heights on the square lattice of `side` × `side` points from (`first`, `first`) every
    /// `spacing` metres, row by row (z then x): `height` at each, each wave split as
    /// sin(a + b) = sin a cos b + cos a sin b into its x and z parts, so the trigonometry is per
    /// row and column, not per point (a 4 001² export in a fraction of a second).
    pub fn heights_on_lattice(&self, first: f64, spacing: f64, side: u32) -> Vec<f64> {
        let period = f64::from(WORLD_PERIOD);
        let at = |i: u32| first + f64::from(i) * spacing;
        let mut heights = vec![0.0; side as usize * side as usize];
        for (k, wave) in self.waves.iter().enumerate() {
            let (m, n) = self.cycles[k];
            let angle =
                |cycles: i32, w: f64| (TAU64 * f64::from(cycles) * w.rem_euclid(period) / period).rem_euclid(TAU64);
            let x: Vec<(f64, f64)> = (0..side).map(|i| angle(m, at(i)).sin_cos()).collect();
            let z: Vec<(f64, f64)> =
                (0..side).map(|j| (angle(n, at(j)) + f64::from(wave.w)).rem_euclid(TAU64).sin_cos()).collect();
            let amplitude = f64::from(wave.z);
            for (row, &(sz, cz)) in heights.chunks_exact_mut(side as usize).zip(&z) {
                for (h, &(sx, cx)) in row.iter_mut().zip(&x) {
                    *h += amplitude * (sx * cz + cx * sz);
                }
            }
        }
        heights
    }

    /// Height at world (x, z), in f64 (the camera's ground, the CPU side of the GPU's relief).
    pub fn height(&self, x: f64, z: f64) -> f64 {
        (0..WAVES).map(|k| f64::from(self.waves[k].z) * self.phase(k, x, z).sin()).sum()
    }

    /// The per-wave phases at `origin` for the GPU: (sin, cos) of u_k · O + φ_k, two waves per
    /// `Vec4`.
    pub fn phases(&self, origin: DVec2) -> [Vec4; WAVES / 2] {
        let phase = |k: usize| {
            let theta = self.phase(k, origin.x, origin.y);
            (theta.sin() as f32, theta.cos() as f32)
        };
        std::array::from_fn(|i| {
            let (s0, c0) = phase(2 * i);
            let (s1, c1) = phase(2 * i + 1);
            Vec4::new(s0, c0, s1, c1)
        })
    }

    /// The largest height the relief can reach either side of 0 (Σ |a_k|), with a margin for the
    /// GPU's f32 sums.
    pub fn height_bound(&self) -> f32 {
        1.001 * self.waves.iter().map(|w| w.z.abs()).sum::<f32>() + 1e-3
    }

    /// The steepest slope the relief can have (Σ a_k |u_k|): bounds a cell's heights.
    pub fn slope_bound(&self) -> f32 {
        self.waves.iter().map(|w| w.z * Vec2::new(w.x, w.y).length()).sum()
    }
}

/// The stored block: its blades at block-local (x, z) in [0, BLOCK_SIZE)², y = 0, in shuffled
/// order (a prefix is an even thinning, as in a tile of a stored field).
pub fn block_blades(spec: &FieldSpec, seed: u64) -> Vec<BladeInstance> {
    let mut rng = Rng::new(seed ^ 0xb10c);
    (0..spec.block_blades())
        .map(|_| BladeInstance {
            position: [rng.range(0.0, BLOCK_SIZE), 0.0, rng.range(0.0, BLOCK_SIZE)],
            facing: rng.range(0.0, TAU),
            height: rng.range(blades::HEIGHT_RANGE.0, blades::HEIGHT_RANGE.1),
            width: rng.range(blades::WIDTH_RANGE.0, blades::WIDTH_RANGE.1),
            stiffness: rng.range(blades::STIFFNESS_RANGE.0, blades::STIFFNESS_RANGE.1),
            variation: (rng.next_u64() & 0xffff_ffff) as u32,
        })
        .collect()
}

/// How far from the world's origin, in x and z, a block field is drawn (metres). The GPU holds
/// a cell's integer coordinates in 32 bits (`render::field_gpu::Origin::cell`,
/// `shaders/common/field.glsl`), and the cull adds up to 127 rings to the camera's cell: 2³¹ cells of
/// `BLOCK_SIZE` end at 8.59e9 m, so 8e9 m keeps every cell it visits in range. (Positions are
/// `f32`: out there a camera moves in steps of 512 m, and wrapping the index would not help.)
pub const MAX_DISTANCE: f32 = 8.0e9;
const _: () = assert!((MAX_DISTANCE / BLOCK_SIZE) as i64 + 128 < i32::MAX as i64);

/// Refuse a camera at `position` over a block field farther than `MAX_DISTANCE` from the
/// origin in x or z (or not finite): one line for the caller's `error:`.
pub fn check_camera(position: glam::Vec3) -> Result<(), String> {
    let within = |v: f32| v.abs() <= MAX_DISTANCE;
    if within(position.x) && within(position.z) {
        return Ok(());
    }
    Err(format!(
        "a camera at x {} m, z {} m is past {MAX_DISTANCE:e} m from the origin, where a block field ends (its \
         cells are indexed in 32 bits)",
        position.x, position.z
    ))
}

/// The integer cell holding world (x, z).
pub fn cell_of(x: f64, z: f64) -> (i64, i64) {
    let b = f64::from(BLOCK_SIZE);
    ((x / b).floor() as i64, (z / b).floor() as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The terrain pass bounds its chunks by ± `height_bound`: no height the relief reaches, over
    /// several seeds and far from the origin, lies outside; and the bound is not loose by more
    /// than the waves' sum can explain (the highest sample reaches half of it).
    #[test]
    fn the_relief_stays_within_its_height_bound() {
        for seed in [1, 3, 11] {
            let relief = Relief::generate(seed);
            let bound = f64::from(relief.height_bound());
            let mut highest = 0.0f64;
            for i in 0..20_000 {
                let (x, z) = (f64::from(i) * 0.37 - 3000.0, f64::from(i % 211) * 1.9 + 1.0e5);
                let h = relief.height(x, z);
                assert!(h.abs() <= bound, "seed {seed}: height {h} at ({x}, {z}) past ±{bound}");
                highest = highest.max(h.abs());
            }
            assert!(highest > 0.5 * bound, "seed {seed}: highest {highest} of bound {bound}");
        }
    }

    #[test]
    fn the_relief_is_gentle_and_its_phases_rebuild_it_anywhere() {
        let relief = Relief::generate(3);
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for i in 0..400 {
            let h = relief.height(f64::from(i) * 0.7, f64::from(i) * -1.3);
            (lo, hi) = (lo.min(h), hi.max(h));
        }
        assert!(hi - lo > 0.5 && hi - lo < 4.0, "relief {lo}..{hi}");
        assert!(relief.slope_bound() < 0.6, "{}", relief.slope_bound());
        // Far from the origin, the GPU's camera-relative sum equals the f64 height.
        let origin = DVec2::new(100_000.0, -100_004.0);
        let phases = relief.phases(origin);
        let local = Vec2::new(1.25, -2.5);
        let gpu: f32 = (0..WAVES)
            .map(|k| {
                let w = relief.waves[k];
                let p = phases[k / 2];
                let (s, c) = if k % 2 == 0 { (p.x, p.y) } else { (p.z, p.w) };
                let a = w.x * local.x + w.y * local.y;
                w.z * (s * a.cos() + c * a.sin())
            })
            .sum();
        let exact = relief.height(origin.x + f64::from(local.x), origin.y + f64::from(local.y));
        assert!((f64::from(gpu) - exact).abs() < 1e-5, "{gpu} vs {exact}");
        // The world repeats every WORLD_PERIOD.
        let period = f64::from(WORLD_PERIOD);
        assert!((relief.height(3.5, -7.25) - relief.height(3.5 + 100.0 * period, -7.25 - 100.0 * period)).abs() < 1e-6);
    }

    #[test]
    fn the_hills_are_hundreds_of_metres_long_and_the_gentle_relief_is_unchanged() {
        let hills = Relief::of_kind(ReliefKind::Hills, 1);
        let longest = hills.waves.iter().map(|w| TAU / Vec2::new(w.x, w.y).length()).fold(0.0, f32::max);
        assert!((700.0..900.0).contains(&longest), "{longest} m");
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for i in 0..2000 {
            let h = hills.height(f64::from(i) * 3.1, f64::from(i) * -1.7);
            (lo, hi) = (lo.min(h), hi.max(h));
        }
        assert!(hi - lo > 30.0 && f64::from(hills.height_bound()) >= hi.max(-lo), "hills {lo}..{hi}");
        assert!(hills.slope_bound() < 1.0, "{}", hills.slope_bound());
        // The gentle relief keeps the wave vectors it had on the 1 km lattice, bit for bit.
        let gentle = Relief::generate(1);
        let k = TAU / GENTLE_PERIOD;
        for (w, &(m, n)) in gentle.waves.iter().zip(&gentle.cycles) {
            assert_eq!((m % 20, n % 20), (0, 0));
            assert_eq!((w.x, w.y), ((m / 20) as f32 * k, (n / 20) as f32 * k));
        }
        assert_ne!(hills, gentle);
    }

    #[test]
    fn a_block_holds_its_density_inside_its_square() {
        let spec = FieldSpec { size: None, density: 400.0 };
        let block = block_blades(&spec, 1);
        assert_eq!(block.len() as u64, spec.block_blades());
        assert_eq!(block.len(), 6400);
        assert!(block
            .iter()
            .all(|b| (0.0..BLOCK_SIZE).contains(&b.position[0]) && (0.0..BLOCK_SIZE).contains(&b.position[2])));
        assert_eq!(cell_of(-0.5, 4.0), (-1, 1));
    }

    #[test]
    fn cameras_past_the_cell_index_are_refused() {
        assert!(check_camera(glam::Vec3::new(MAX_DISTANCE, 1.7, -MAX_DISTANCE)).is_ok());
        assert!(check_camera(glam::Vec3::new(1.0e10, 1.7, 0.0)).is_err());
        assert!(check_camera(glam::Vec3::new(0.0, 1.7, -1.0e10)).is_err());
        assert!(check_camera(glam::Vec3::new(f32::NAN, 1.7, 0.0)).is_err());
        // The farthest cell the cull visits still fits.
        let (x, _) = cell_of(f64::from(MAX_DISTANCE), 0.0);
        assert!(x + 128 < i64::from(i32::MAX), "{x}");
    }
}
