//! The analytic wind field's parameters of one frame (`Params`): the block its GPU pass reads
//! (`WindParams` of `shaders/wind/analytic_corners.comp`), filled by the CPU per frame from the
//! wind, the frame's O (f64) and time.

use bytemuck::{Pod, Zeroable};

use super::WindInput;
use crate::render::animation;
use crate::render::gpu_constants as gpu;
use crate::wind::{Attenuation, KEYFRAME_WIND_SCALE};

/// Calm areas the GPU field holds (`MAX_CALM_AREAS` of `shaders/common/shared.glsl`).
pub const MAX_CALM_AREAS: usize = gpu::MAX_CALM_AREAS as usize;
/// Levels the GPU field holds at most (`WIND_LEVELS`).
pub const WIND_LEVELS: usize = gpu::WIND_LEVELS as usize;

/// The analytic field's parameters of one frame: `WindParams` of
/// `shaders/wind/analytic_corners.comp` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Params {
    /// Direction (x, z), mean speed in m/s, and 0 without a global wind, 1 steady, 2 with gusts.
    pub global: [f32; 4],
    /// The four waves' phases at O at the frame's time, in [0, 2π).
    pub phases: [f32; 4],
    /// Waves 0 and 1, then 2 and 3: wave vectors (x, z) in rad/m.
    pub waves: [[f32; 4]; 2],
    /// The first corner relative to O (x, z), the cluster edge, 0.
    pub grid: [f32; 4],
    /// Corners per side of a level, corners over every level, 1 with delayed attenuation, levels.
    pub shape: [u32; 4],
    /// Sources, colliders, calm areas, 0.
    pub counts: [u32; 4],
    /// Per level, innermost first: its first corner relative to O (x, z), its spacing, 0
    /// (`field_gpu::wind_level`; a stored field has one level, its grid).
    pub levels: [[f32; 4]; WIND_LEVELS],
    /// Calm areas: min (x, z), max (x, z) relative to O.
    pub calm: [[f32; 4]; MAX_CALM_AREAS],
    /// The Perlin field's layers (`perlin::fill_params`; zero for the analytic field): the
    /// offset at O (x, y texels), c_i (texels per metre), k_i times the mean speed (m/s).
    pub perlin: [[f32; 4]; 3],
    /// Each layer's direction d_i (x, z), 0, 0.
    pub perlin_dirs: [[f32; 4]; 3],
    /// Per wind level, each layer's mip level of the noise, 0.
    pub perlin_mips: [[u32; 4]; WIND_LEVELS],
    /// The fluid grid (`fluid::fill_params`; zero for the other fields): cells per axis, the
    /// inflow faces (bits x-, x+, z-, z+).
    pub fluid_dims: [u32; 4],
    /// The window's toroidal base (x, y, z), the pressure iterations.
    pub fluid_base: [u32; 4],
    /// Sources, colliders, 0, 0.
    pub fluid_counts: [u32; 4],
    /// A cell's edges (x, y, z) in m, the step dt in s.
    pub fluid_cell: [f32; 4],
    /// The window's first corner relative to O (x, z), the blades' sample height (m), the blend
    /// band (cells).
    pub fluid_corner: [f32; 4],
    /// The diffusion's ν dt / h² per axis, unused (the pressure's weights are pushed per
    /// iteration, `fluid::pressure_weight`).
    pub fluid_coef: [f32; 4],
    /// Sources: x, z relative to O, height above the ground (m), the jet's speed (m/s).
    pub fluid_sources: [[f32; 4]; gpu::MAX_FLUID_SOURCES as usize],
    /// Per collider: its centre (x, height above the ground, z relative to O), its radii.
    pub fluid_colliders: [[f32; 4]; 2 * gpu::MAX_FLUID_COLLIDERS as usize],
}

impl Params {
    /// The parameters of the frame `input` describes.
    pub fn new(input: &WindInput) -> Self {
        let (wind, grid, o) = (input.wind, input.grid, input.origin);
        let (sources, colliders) = animation::emitter_counts(wind);
        let calm = wind.calm.len().min(MAX_CALM_AREAS);
        let mut params = Params {
            grid: [grid.origin, grid.origin, grid.cluster_size, 0.0],
            shape: [
                grid.corners_per_side(),
                input.levels * grid.corner_count(),
                u32::from(input.attenuation == Attenuation::Blade),
                input.levels,
            ],
            counts: [sources, colliders, calm as u32, 0],
            ..Zeroable::zeroed()
        };
        if let Some(g) = &wind.global {
            let dir = g.direction_f64();
            let speed = g.strength * KEYFRAME_WIND_SCALE;
            params.global = [dir.x as f32, dir.y as f32, speed, if g.gusts { 2.0 } else { 1.0 }];
            params.phases = g.phases(o, input.time).map(|p| p as f32);
            let k = g.wave_vectors().map(|k| k.as_vec2());
            params.waves = [[k[0].x, k[0].y, k[1].x, k[1].y], [k[2].x, k[2].y, k[3].x, k[3].y]];
        }
        for (level, slot) in params.levels.iter_mut().enumerate().take(input.levels as usize) {
            let g = match input.levels {
                1 => *grid,
                _ => crate::render::field_gpu::wind_level(grid.cluster_size, level as u32),
            };
            *slot = [g.origin, g.origin, g.cluster_size, 0.0];
        }
        for (slot, c) in params.calm.iter_mut().zip(&wind.calm) {
            let (min, max) = (c.min.as_dvec2() - o, c.max.as_dvec2() - o);
            *slot = [min.x as f32, min.y as f32, max.x as f32, max.y as f32];
        }
        params
    }
}
