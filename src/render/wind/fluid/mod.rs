//! The fluid wind (`--wind-field fluid`): Zhang Xia's §2, after Stam's stable fluids (1999), on
//! the GPU. A 3-D grid of cell-centred velocities, `--fluid-grid NX,NY,NZ` cells of
//! `--fluid-cell DXZ,DY` metres, follows the camera by whole cells in x and z (a
//! `camera_grid::CameraGrid`: toroidal, f64 world cells) and stands on the local ground in y.
//! Each frame takes one step of `dt` (the fixed step, `--dt`): the cells that entered start from
//! the analytic field, then the sources, calm areas and colliders (f of eq. 2), the diffusion
//! (eq. 4, `DIFFUSE_ITERATIONS` Jacobi iterations), the self-advection (§2.3.3) and the
//! projection (§2.3.6, `PRESSURE_ITERATIONS` Jacobi iterations with Chebyshev weights,
//! `pressure_weight`, on the pressure's Poisson equation, warm-started from the last step's
//! pressure). `pass::FluidPass` records them as steps of one pass, then the corners: a corner inside the grid takes the fluid's wind at
//! `SAMPLE_HEIGHT` above the ground (Zhang Xia's tri-linear interpolation, §3.2.2), blended
//! linearly into the analytic field over the grid's outer `BLEND_CELLS` cells; past the grid the
//! analytic field (the global wind with gusts and the point sources of eq. 4.1) holds.
//!
//! meadow's choices, where the paper leaves them open:
//! - **Boundaries** (ghost cells, `shaders/wind/fluid.glsl`): a face the global wind crosses
//!   inwards takes the analytic wind (inflow), the others the edge cell's (zero-gradient
//!   outflow) with the pressure 0 past them; the ground and the top mirror the cell inside with
//!   its vertical velocity negated (no penetration, free slip) and the pressure's gradient 0.
//! - **Sources** inject a downward jet at their height (`--source …,HEIGHT`, 0.5 m by default):
//!   each relaxes the velocity towards (0, −ω·8 m/s, 0) over `SOURCE_TIME`, in a Gaussian of
//!   `SOURCE_RADIUS` about its point. The ground turns the jet into an outward flow along it, as
//!   eq. 4.1 blows; a radial source of eq. 4.1 itself is a pure divergence, which the projection
//!   removes whole.
//! - **Colliders** are solid cells (velocity 0) where they are this frame: their height is taken
//!   above the ground under their centre (a block field's relief; a stored field's y = 0).
//! - **Calm areas** damp the velocity at `CALM_DAMPING` per second.
//! - **Brute force** (`--brute-force`) keeps the thesis' CPU corners: the fluid needs the GPU
//!   path, and `cli` refuses the two together.

pub mod pass;
pub mod scheme;

use std::cell::RefCell;
use std::rc::Rc;

use bytemuck::Zeroable;
use glam::{DVec2, DVec3, I64Vec3, UVec3};

use super::analytic::emitters_relative;
use super::params::Params;
use super::{WindField, WindInput, WindSetup};
use crate::error::Result;
use crate::render::camera_grid::{CameraGrid, GridShape, Scroll};
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::wind::FrameForces;
use crate::vk::Device;
use crate::wind::{FluidGrid, KEYFRAME_WIND_SCALE};

/// Jacobi iterations of the diffusion (eq. 4) per step.
pub const DIFFUSE_ITERATIONS: u32 = 2;
/// Iterations of the pressure per step: one cycle of `pressure_weight`.
pub const PRESSURE_ITERATIONS: u32 = 8;
/// The bounds [λ_min, λ_max] on the eigenvalues of diag⁻¹ (D G) that the pressure's Chebyshev
/// weights are made for: λ_max = 2 bounds the wide stencil's (Σ_k (1 − cos 2θ_k) weighted by
/// its axes' share of the diagonal); below λ_min lie the smoothest modes, which each cycle still
/// damps, more slowly.
pub const PRESSURE_SPECTRUM: [f32; 2] = [0.2, 2.0];

/// The weight ω_k of the pressure's iteration `k` (k ≥ 0, cycling every `PRESSURE_ITERATIONS`):
/// Jacobi with the Chebyshev semi-iteration's weights (Richardson's method on diag⁻¹ (D G), with
/// the weights the reciprocals of the roots of the Chebyshev polynomial of degree
/// `PRESSURE_ITERATIONS` over `PRESSURE_SPECTRUM`), taken alternately from either end so that the
/// large weights, which amplify the high modes for a step, never follow one another. Per
/// iteration it costs what weighted Jacobi does, and 8 of them cut the RMS divergence of the
/// default grid 58×, where 16 at ω = 0.8 cut it 34× (`tests/fluid.rs`).
pub fn pressure_weight(k: u32) -> f32 {
    let n = PRESSURE_ITERATIONS;
    let i = k % n;
    let root = if i.is_multiple_of(2) { i / 2 } else { n - 1 - i / 2 };
    let [a, b] = PRESSURE_SPECTRUM;
    let t = std::f32::consts::PI * (2 * root + 1) as f32 / (2 * n) as f32;
    1.0 / (0.5 * (b + a) + 0.5 * (b - a) * t.cos())
}

/// The wind's kinematic viscosity ν in m²/s: an eddy viscosity (air's own, 1.5e-5, would not
/// show at these cells).
pub const VISCOSITY: f32 = 0.05;
/// A source's Gaussian radius in metres.
pub const SOURCE_RADIUS: f32 = 1.0;
/// The time over which a source brings the velocity to its jet's, in seconds.
pub const SOURCE_TIME: f32 = 0.25;
/// The velocity's damping rate in a calm area, per second.
pub const CALM_DAMPING: f32 = 4.0;
/// The height above the ground at which the blades sample the fluid, in metres.
pub const SAMPLE_HEIGHT: f32 = 0.5;
/// The grid's outer cells over which the fluid blends into the analytic field.
pub const BLEND_CELLS: f32 = 2.0;
/// Sources the fluid injects (`MAX_FLUID_SOURCES`).
pub const MAX_SOURCES: usize = gpu::MAX_FLUID_SOURCES as usize;
/// Colliders it holds as solid cells (`MAX_FLUID_COLLIDERS`).
pub const MAX_COLLIDERS: usize = gpu::MAX_FLUID_COLLIDERS as usize;

/// The camera grid of a fluid grid's shape: one level, RGBA32F velocities.
pub fn grid_shape(grid: &FluidGrid) -> GridShape {
    let cell = DVec3::new(f64::from(grid.cell[0]), f64::from(grid.cell[1]), f64::from(grid.cell[0]));
    GridShape { dims: UVec3::from_array(grid.dims), cell, levels: 1, texel_bytes: 16 }
}

/// Bytes the fluid's images hold on the GPU: three velocity grids (RGBA32F), two pressures
/// (R32F) and the divergence with its row's diagonal (RG32F).
pub fn grid_bytes(grid: &FluidGrid) -> u64 {
    let inflow = pass::inflow_extent(grid);
    grid_shape(grid).cells_per_level() * (3 * 16 + 2 * 4 + 8) + u64::from(inflow.width * inflow.height) * 16
}

/// The window and what entered it this frame, shared by the field's update and its pass.
pub struct FluidWindow {
    /// Where the window lies on the world lattice.
    pub grid: CameraGrid,
    /// The cells that entered this frame (filled by the pass's first step).
    pub scroll: Option<Scroll>,
}

/// The fluid wind field.
pub struct FluidWind {
    grid: FluidGrid,
    params: Rc<RefCell<Params>>,
    window: Rc<RefCell<FluidWindow>>,
    /// The pass's images, once built, for a test's readback.
    images: Rc<RefCell<Option<pass::FluidImages>>>,
    /// The images the last built pass holds, until the renderer imports them.
    tracked: RefCell<Vec<(crate::vk::Resource, Vec<crate::vk::Access>)>>,
}

impl FluidWind {
    /// A field of `grid`'s shape (checked by the caller: `FluidGrid::check`).
    pub fn new(grid: FluidGrid) -> Result<Self> {
        let shape = CameraGrid::new(grid_shape(&grid)).map_err(crate::error::Error::BadInput)?;
        let window = FluidWindow { grid: shape, scroll: None };
        Ok(Self {
            grid,
            params: Rc::new(RefCell::new(Zeroable::zeroed())),
            window: Rc::new(RefCell::new(window)),
            images: Rc::default(),
            tracked: RefCell::default(),
        })
    }

    /// What a test reads of the field after a frame: its parameters and its window.
    pub fn probe(&self) -> FluidProbe {
        FluidProbe { params: self.params.clone(), window: self.window.clone() }
    }
}

/// A view of a fluid field's last frame, kept when the field is handed to a renderer.
pub struct FluidProbe {
    params: Rc<RefCell<Params>>,
    window: Rc<RefCell<FluidWindow>>,
}

impl FluidProbe {
    /// The last frame's parameters.
    pub fn params(&self) -> Params {
        *self.params.borrow()
    }

    /// The window's first world cell (`None` before the first frame).
    pub fn window(&self) -> Option<I64Vec3> {
        self.window.borrow().grid.window(0)
    }
}

/// The inflow faces (bits x-, x+, z-, z+) under a global wind towards `direction` (x, z).
pub fn upwind_faces(direction: DVec2, speed: f64) -> u32 {
    if speed <= 0.0 {
        return 0;
    }
    let bit = |on: bool, b: u32| if on { b } else { 0 };
    let eps = 1e-6;
    bit(direction.x > eps, 1) | bit(direction.x < -eps, 2) | bit(direction.y > eps, 4) | bit(direction.y < -eps, 8)
}

/// Fill the fluid's part of `params` for a window whose first cell is `first` (scrolled to
/// toroidal base `base`) under `input`.
pub fn fill_params(params: &mut Params, grid: &FluidGrid, (first, base): (I64Vec3, UVec3), input: &WindInput) {
    let shape = grid_shape(grid);
    let h = shape.cell;
    let o = input.origin;
    let corner = DVec2::new(first.x as f64 * h.x, first.z as f64 * h.z) - o;
    let wind = input.wind;
    let faces = wind.global.as_ref().map_or(0, |g| upwind_faces(g.direction_f64(), f64::from(g.strength)));
    params.fluid_dims = [grid.dims[0], grid.dims[1], grid.dims[2], faces];
    params.fluid_base = [base.x, base.y, base.z, PRESSURE_ITERATIONS];
    let dt = input.dt;
    params.fluid_cell = [h.x as f32, h.y as f32, h.z as f32, dt];
    params.fluid_corner = [corner.x as f32, corner.y as f32, SAMPLE_HEIGHT, BLEND_CELLS];
    let a = |edge: f64| VISCOSITY * dt / (edge * edge) as f32;
    params.fluid_coef = [a(h.x), a(h.y), a(h.z), 0.0];
    let sources = wind.sources.iter().take(MAX_SOURCES);
    for (slot, s) in params.fluid_sources.iter_mut().zip(sources) {
        let p = (s.position_f64(input.time) - o).as_vec2();
        *slot = [p.x, p.y, s.height, s.power * KEYFRAME_WIND_SCALE];
    }
    let colliders: Vec<_> = wind.colliders.iter().take(MAX_COLLIDERS).collect();
    for (i, c) in colliders.iter().enumerate() {
        let centre = c.center_f64(input.time);
        let at = DVec2::new(centre.x, centre.z);
        let ground = input.ground.map_or(0.0, |g| g.height(at.x, at.y));
        let p = (at - o).as_vec2();
        params.fluid_colliders[2 * i] = [p.x, (centre.y - ground) as f32, p.y, 0.0];
        params.fluid_colliders[2 * i + 1] = c.radii.extend(0.0).to_array();
    }
    params.fluid_counts = [wind.sources.len().min(MAX_SOURCES) as u32, colliders.len() as u32, 0, 0];
}

impl WindField for FluidWind {
    fn name(&self) -> &'static str {
        "fluid"
    }

    fn update(&self, forces: &mut FrameForces, input: &WindInput) {
        forces.emitters.write(0, &emitters_relative(input.wind, input.origin, input.time));
        if input.cpu_corners {
            // No GPU step without the cull: the thesis' CPU corners of the analytic field.
            super::AnalyticWind::new().update(forces, input);
            return;
        }
        let mut window = self.window.borrow_mut();
        let mut first = window.grid.window_around(0, input.camera);
        first.y = 0;
        let scroll = window.grid.scroll_to(0, first);
        let base = first.rem_euclid(UVec3::from_array(self.grid.dims).as_i64vec3()).as_uvec3();
        window.scroll = scroll;
        let mut params = Params::new(input);
        fill_params(&mut params, &self.grid, (first, base), input);
        *self.params.borrow_mut() = params;
    }

    fn passes(&self, device: &Device, setup: &WindSetup) -> Result<Vec<Box<dyn Pass>>> {
        self.window.borrow_mut().grid.invalidate();
        let shared =
            pass::Shared { params: self.params.clone(), window: self.window.clone(), images: self.images.clone() };
        let pass = pass::FluidPass::new(device, setup, &self.grid, shared)?;
        *self.tracked.borrow_mut() = pass.tracked();
        Ok(vec![Box::new(pass)])
    }

    fn tracked(&self) -> Vec<(crate::vk::Resource, Vec<crate::vk::Access>)> {
        self.tracked.borrow_mut().drain(..).collect()
    }

    fn stateful(&self) -> bool {
        true
    }

    fn state(&self) -> Option<(ash::vk::Image, ash::vk::Extent3D, UVec3)> {
        let images = (*self.images.borrow())?;
        let base = self.params.borrow().fluid_base;
        Some((images.velocity[0], images.extent, UVec3::new(base[0], base[1], base[2])))
    }
}
