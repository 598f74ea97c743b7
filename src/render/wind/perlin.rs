//! Belyaev's Perlin wind (§3.2): W[u] = Σ_{i=1..3} k_i T[w_i t + c_i R_i u], three layers of one
//! cyclic noise texture T at scales c_i, turned by R_i and scrolled by w_i, summed with gains k_i.
//! meadow's choices, where the paper leaves them open:
//! - **T** is tileable 2-D gradient noise (Perlin's, with a quintic fade) made by meadow at start,
//!   `NOISE_TEXELS`² texels over `NOISE_CELLS`² lattice cells, two independent channels (n_a,
//!   n_b) in [-1, 1], with its box-filtered mip chain (`Noise`).
//! - **A layer's wind** is a vector in the layer's frame, whose x axis is the layer's direction
//!   d_i: (1 + `STRENGTH`·n_a, `SWIRL`·n_b), so each layer blows along d_i on average, its strength
//!   and direction varying with the noise. W = s · Σ k_i (a_i d_i + b_i d_i⊥), s the global wind's
//!   mean speed in m/s: no global wind, no wind.
//! - **The layers** (`LAYERS`) follow the global wind: d_i is its direction turned by a few
//!   degrees, and the pattern moves downwind at a multiple of its speed. Belyaev's w_i t is then
//!   −c_i (s_i t, 0) in the layer's frame: x_i = c_i (d_i · u − s_i t, d_i⊥ · u), in texels.
//! - **Band-limited**: a wind level of corner spacing h samples layer i at the mip level where a
//!   texel spans at least c_i·h texels of the finest (`mip_for`), so a fine octave does not alias
//!   on the coarse levels that carry the wind to 4 km.
//!
//! On the GPU the analytic field's corner pass takes the variant `perlin`
//! (`shaders/wind/analytic_corners.comp`, `shaders/wind/perlin.glsl`): point sources and calm
//! areas act as in the analytic field, the noise replaces its global wind and gusts. Each layer's
//! offset at O, c_i (d_i · O − s_i t, d_i⊥ · O), is folded into the texture's period in f64 on the
//! CPU, so a field 100 km out is as exact as at the origin. With `--brute-force` the CPU writes
//! the corners with the same arithmetic (`corner_winds`).

use std::cell::RefCell;
use std::f64::consts::TAU;
use std::rc::Rc;

use bytemuck::Zeroable;
use glam::{DVec2, Vec2, Vec4};

use super::analytic::emitters_relative;
use super::corners_pass::{AnalyticCornersPass, CornerVariant};
use super::params::Params;
use super::{WindField, WindInput, WindSetup};
use crate::error::Result;
use crate::render::animation;
use crate::render::graph::Pass;
use crate::render::wind::FrameForces;
use crate::vk::Device;
use crate::wind::{Wind, KEYFRAME_WIND_SCALE};

/// Texels per side of the noise's finest level (`PERLIN_TEXELS` of `shaders/common/shared.glsl`).
pub const NOISE_TEXELS: u32 = crate::render::gpu_constants::PERLIN_TEXELS;
/// Lattice cells per side of the noise: its period.
pub const NOISE_CELLS: u32 = 16;
/// Mip levels of the noise (128² down to 1²).
pub const NOISE_LEVELS: u32 = NOISE_TEXELS.ilog2() + 1;
/// How much the noise varies a layer's strength (n_a's gain).
pub const STRENGTH: f32 = 0.6;
/// How much the noise turns a layer's wind across its direction (n_b's gain).
pub const SWIRL: f32 = 0.35;

/// One layer of the sum: its lattice cell in metres (c_i = texels per cell / cell), its turn from
/// the global wind's direction in degrees, its pattern's speed over the global wind's, its gain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// The noise's lattice cell in the world, metres: the size of the layer's gusts.
    pub cell: f64,
    /// Degrees from the global wind's direction.
    pub turn_deg: f64,
    /// The pattern's speed over the global wind's.
    pub speed: f64,
    /// k_i.
    pub gain: f32,
}

/// Belyaev's three layers: gusts of 32, 8 and 2 m, the finer ones faster and turned a little.
pub const LAYERS: [Layer; 3] = [
    Layer { cell: 32.0, turn_deg: 0.0, speed: 1.0, gain: 0.6 },
    Layer { cell: 8.0, turn_deg: 20.0, speed: 1.3, gain: 0.3 },
    Layer { cell: 2.0, turn_deg: -15.0, speed: 1.7, gain: 0.1 },
];

impl Layer {
    /// c_i: texels of the finest level per metre.
    pub fn scale(&self) -> f64 {
        f64::from(NOISE_TEXELS / NOISE_CELLS) / self.cell
    }

    /// d_i under a global wind towards `direction_deg`.
    pub fn direction(&self, direction_deg: f64) -> DVec2 {
        let a = (direction_deg + self.turn_deg).to_radians();
        DVec2::new(a.cos(), a.sin())
    }

    /// The layer's texture offset at world `origin` and `time` (texels, folded into the period):
    /// c_i (d_i · O − s_i t, d_i⊥ · O) for a global wind of `speed` m/s towards `direction_deg`.
    pub fn offset(&self, origin: DVec2, time: f64, (direction_deg, speed): (f64, f64)) -> Vec2 {
        let d = self.direction(direction_deg);
        let across = DVec2::new(-d.y, d.x);
        let x = self.scale() * DVec2::new(d.dot(origin) - self.speed * speed * time, across.dot(origin));
        let period = f64::from(NOISE_TEXELS);
        DVec2::new(x.x.rem_euclid(period), x.y.rem_euclid(period)).as_vec2()
    }
}

/// The mip level at which a wind level of corner spacing `spacing` metres samples `layer`: the
/// finest whose texel spans at least the spacing (c_i·h texels of the finest level).
pub fn mip_for(layer: &Layer, spacing: f64) -> u32 {
    let texels = layer.scale() * spacing;
    let mut level = 0;
    while level + 1 < NOISE_LEVELS && f64::from(1u32 << level) < texels {
        level += 1;
    }
    level
}

/// The noise texture and its mip chain: level m (NOISE_TEXELS >> m texels a side) after level
/// m − 1, row-major, two channels a texel.
pub struct Noise {
    /// Every level's texels.
    pub texels: Vec<[f32; 2]>,
}

/// A lattice point's gradient: a unit vector from a hash of the point (wrapped to the period)
/// and the channel.
fn gradient(x: i64, y: i64, channel: u32) -> DVec2 {
    let n = i64::from(NOISE_CELLS);
    let (x, y) = (x.rem_euclid(n) as u32, y.rem_euclid(n) as u32);
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ channel.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    let angle = f64::from(h) / 4_294_967_296.0 * TAU;
    DVec2::new(angle.cos(), angle.sin())
}

/// Perlin's gradient noise at lattice coordinates `p`, periodic over `NOISE_CELLS`, about [-1, 1].
fn gradient_noise(p: DVec2, channel: u32) -> f64 {
    let (i, f) = (p.floor(), p - p.floor());
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v) = (fade(f.x), fade(f.y));
    let corner = |dx: i64, dy: i64| {
        let g = gradient(i.x as i64 + dx, i.y as i64 + dy, channel);
        g.dot(f - DVec2::new(dx as f64, dy as f64))
    };
    let bottom = corner(0, 0) + u * (corner(1, 0) - corner(0, 0));
    let top = corner(0, 1) + u * (corner(1, 1) - corner(0, 1));
    // A 2-D gradient noise of unit gradients lies within ±√2/2.
    (std::f64::consts::SQRT_2 * (bottom + v * (top - bottom))).clamp(-1.0, 1.0)
}

impl Noise {
    /// Generate the noise at the texel centres and box-filter its mips.
    pub fn generate() -> Self {
        let n = NOISE_TEXELS;
        let per_cell = f64::from(n / NOISE_CELLS);
        let mut texels: Vec<[f32; 2]> = (0..n * n)
            .map(|i| {
                let p = (DVec2::new(f64::from(i % n), f64::from(i / n)) + 0.5) / per_cell;
                [gradient_noise(p, 0) as f32, gradient_noise(p, 1) as f32]
            })
            .collect();
        let (mut base, mut side) = (0usize, n as usize);
        while side > 1 {
            let half = side / 2;
            for y in 0..half {
                for x in 0..half {
                    let at = |dx: usize, dy: usize| texels[base + (2 * y + dy) * side + 2 * x + dx];
                    let sum = [at(0, 0), at(1, 0), at(0, 1), at(1, 1)];
                    let mean = |c: usize| 0.25 * (sum[0][c] + sum[1][c] + sum[2][c] + sum[3][c]);
                    texels.push([mean(0), mean(1)]);
                }
            }
            base += side * side;
            side = half;
        }
        Self { texels }
    }

    /// The first texel of mip level `level`.
    pub fn level_base(level: u32) -> u32 {
        (0..level).map(|l| (NOISE_TEXELS >> l).pow(2)).sum()
    }

    /// Bilinear at `x` (texels of the finest level) in mip level `level`, wrapped: as
    /// `perlin_texel` of `shaders/wind/perlin.glsl`, in f32.
    pub fn sample(&self, x: Vec2, level: u32) -> Vec2 {
        let side = (NOISE_TEXELS >> level) as i32;
        let g = x / (1u32 << level) as f32 - Vec2::splat(0.5);
        let (i, f) = (g.floor(), g - g.floor());
        let base = Self::level_base(level) as usize;
        let texel = |dx: i32, dy: i32| {
            let (tx, ty) = ((i.x as i32 + dx).rem_euclid(side), (i.y as i32 + dy).rem_euclid(side));
            Vec2::from(self.texels[base + (ty * side + tx) as usize])
        };
        let bottom = texel(0, 0).lerp(texel(1, 0), f.x);
        let top = texel(0, 1).lerp(texel(1, 1), f.x);
        bottom.lerp(top, f.y)
    }
}

/// The layers' part of a frame's parameters: per layer its offset at O (texels), c_i, k_i·s (m/s),
/// its direction d_i, and per wind level the mip level of each layer.
pub fn fill_params(params: &mut Params, input: &WindInput) {
    let Some(g) = &input.wind.global else { return };
    let (direction, speed) = (f64::from(g.direction_deg), f64::from(g.strength * KEYFRAME_WIND_SCALE));
    for (i, layer) in LAYERS.iter().enumerate() {
        let offset = layer.offset(input.origin, input.time, (direction, speed));
        let d = layer.direction(direction).as_vec2();
        params.perlin[i] = [offset.x, offset.y, layer.scale() as f32, layer.gain * speed as f32];
        params.perlin_dirs[i] = [d.x, d.y, 0.0, 0.0];
    }
    for (l, mips) in params.perlin_mips.iter_mut().enumerate().take(input.levels as usize) {
        let spacing = f64::from(params.levels[l][2]);
        for (i, layer) in LAYERS.iter().enumerate() {
            mips[i] = mip_for(layer, spacing);
        }
    }
}

/// W at `q` (relative to O) on wind level `level`, from a frame's `params`: as `perlin_wind` of
/// `shaders/wind/perlin.glsl`, in f32.
pub fn wind_at(noise: &Noise, params: &Params, q: Vec2, level: usize) -> Vec2 {
    let mut w = Vec2::ZERO;
    for i in 0..LAYERS.len() {
        let [ox, oy, scale, gain] = params.perlin[i];
        let d = Vec2::new(params.perlin_dirs[i][0], params.perlin_dirs[i][1]);
        let across = Vec2::new(-d.y, d.x);
        let x = Vec2::new(ox, oy) + scale * Vec2::new(d.dot(q), across.dot(q));
        let n = noise.sample(x, params.perlin_mips[level][i]);
        w += gain * ((1.0 + STRENGTH * n.x) * d + SWIRL * n.y * across);
    }
    w
}

/// A frame's parameters for the corner pass's variant `perlin`: the analytic field's (sources,
/// calm areas, levels) without its global wind, whose direction and speed the layers keep, and the
/// layers' (`fill_params`).
pub fn frame_params(input: &WindInput) -> Params {
    let mut params = Params::new(input);
    params.global[3] = 0.0;
    fill_params(&mut params, input);
    params
}

/// The corners of a frame on the CPU (`--brute-force`): the analytic field's sources and calm
/// areas without its global wind, plus W at each corner, times the exposure.
pub fn corner_winds(noise: &Noise, input: &WindInput) -> Vec<Vec4> {
    let still = Wind { global: None, ..input.wind.clone() };
    let origin = input.origin.as_vec2();
    let mut corners = animation::corner_forces_at(input.grid, origin, &still, input.time as f32, input.attenuation);
    let params = frame_params(&WindInput { levels: 1, ..*input });
    for (i, corner) in corners.iter_mut().enumerate() {
        let w = wind_at(noise, &params, input.grid.corner_position(i as u32), 0) * corner.w;
        *corner += Vec4::new(w.x, 0.0, w.y, 0.0);
    }
    corners
}

/// The Perlin wind field.
pub struct PerlinWind {
    params: Rc<RefCell<Params>>,
    noise: Noise,
}

impl Default for PerlinWind {
    fn default() -> Self {
        Self { params: Rc::new(RefCell::new(Zeroable::zeroed())), noise: Noise::generate() }
    }
}

impl WindField for PerlinWind {
    fn name(&self) -> &'static str {
        "perlin"
    }

    fn update(&self, forces: &mut FrameForces, input: &WindInput) {
        forces.emitters.write(0, &emitters_relative(input.wind, input.origin, input.time));
        if input.cpu_corners {
            forces.corners.write(0, &corner_winds(&self.noise, input));
        } else {
            *self.params.borrow_mut() = frame_params(input);
        }
    }

    fn passes(&self, device: &Device, setup: &WindSetup) -> Result<Vec<Box<dyn Pass>>> {
        let noise = CornerVariant::Perlin(self.noise.texels.as_slice());
        Ok(vec![Box::new(AnalyticCornersPass::new(device, setup, self.params.clone(), noise)?)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_tiles_and_stays_within_one() {
        let noise = Noise::generate();
        let n = NOISE_TEXELS as usize;
        assert_eq!(noise.texels.len() as u32, Noise::level_base(NOISE_LEVELS));
        assert!(noise.texels.iter().all(|t| t[0].abs() <= 1.0 && t[1].abs() <= 1.0));
        // A period apart, the same noise; and it varies.
        let p = DVec2::new(3.3, 7.9);
        let shifted = p + DVec2::splat(f64::from(NOISE_CELLS));
        assert!((gradient_noise(p, 0) - gradient_noise(shifted, 0)).abs() < 1e-9);
        let spread =
            noise.texels[..n * n].iter().map(|t| t[0]).fold((1.0f32, -1.0f32), |(l, h), v| (l.min(v), h.max(v)));
        assert!(spread.0 < -0.5 && spread.1 > 0.5, "{spread:?}");
        // Sampling wraps: x and x + the period read the same.
        let x = Vec2::new(5.25, 120.5);
        assert_eq!(noise.sample(x, 1), noise.sample(x + Vec2::splat(NOISE_TEXELS as f32), 1));
    }

    #[test]
    fn each_layer_scrolls_downwind_at_its_speed() {
        let noise = Noise::generate();
        let (direction, speed) = (30.0, 4.0);
        for layer in LAYERS {
            let d = layer.direction(direction);
            let sample = |p: DVec2, t: f64| {
                let o = layer.offset(p, t, (direction, speed));
                noise.sample(o, 0)
            };
            // What is at p at t is at p + d s_i Δ at t + Δ.
            let (p, dt) = (DVec2::new(12.5, -3.0), 0.75);
            let moved = p + d * layer.speed * speed * dt;
            assert!((sample(p, 1.0) - sample(moved, 1.0 + dt)).abs().max_element() < 1e-3, "{layer:?}");
            assert!((sample(p, 1.0) - sample(p, 1.0 + dt)).abs().max_element() > 1e-3, "{layer:?} moves");
        }
    }

    #[test]
    fn coarse_levels_read_coarse_mips() {
        let layer = LAYERS[2];
        assert_eq!(mip_for(&layer, 0.25), 0);
        assert_eq!(mip_for(&layer, 1.0), 2, "4 texels a metre: a 1 m spacing reads texels of 4");
        assert_eq!(mip_for(&layer, 128.0), NOISE_LEVELS - 1);
        assert!(mip_for(&LAYERS[0], 1.0) < mip_for(&LAYERS[2], 1.0));
    }
}
