//! Wind fields (issue #29's seam): what produces, each step, the wind every blade response
//! samples through one GLSL include (`shaders/wind/wind_field.glsl`). A field's quantity is the
//! wind velocity in m/s (x, y, z) and the calm-area exposure that delayed attenuation uses (thesis
//! 4.5); each response maps it to its own input (the keyframes through the fixed scale
//! `wind::KEYFRAME_WIND_SCALE`, `shaders/animation/forces.glsl`). A field writes its CPU part of a
//! frame (`update`) and adds the compute passes that produce the field on the GPU (`passes`).
//!
//! The second, `perlin::PerlinWind` (`--wind-field perlin`), is Belyaev's §3.2: three layers of a
//! scrolling noise texture in place of the global wind and its gusts.
//!
//! The first field, `analytic::AnalyticWind`, is the thesis' wind: the global wind with gusts,
//! moving point sources (eq. 4.1) and calm areas, at the cluster corners (eq. 3.6–3.8): a
//! stored field's one grid, or a block field's `WIND_LEVELS` nested levels out to 4 km
//! (`field_gpu::wind_level`; a blade takes the finest level that holds it,
//! `shaders/wind/wind_field.glsl`). With the cull its pass evaluates them on the GPU (`corners_pass`); with
//! `--brute-force` the CPU writes them, as the thesis did (Table 6.2 measures that path).

pub mod analytic;
mod corners_pass;
pub mod fluid;
mod frame_forces;
pub mod params;
pub mod perlin;

pub use analytic::AnalyticWind;
pub use fluid::FluidWind;
pub use frame_forces::FrameForces;
pub use perlin::PerlinWind;

use ash::vk;
use glam::DVec2;

use crate::error::Result;
use crate::render::graph::Pass;
use crate::render::specialization::Specialization;
use crate::scene::clusters::ClusterGrid;
use crate::vk::Device;
pub use crate::wind::FieldKind;
use crate::wind::{Attenuation, Wind};

/// The library's field of `kind`, built (`fluid`: the fluid's grid, checked here).
pub fn build(kind: FieldKind, fluid: &crate::wind::FluidGrid) -> Result<Box<dyn WindField>> {
    Ok(match kind {
        FieldKind::Analytic => Box::new(AnalyticWind::new()),
        FieldKind::Perlin => Box::new(PerlinWind::default()),
        FieldKind::Fluid => Box::new(FluidWind::new(*fluid)?),
    })
}

/// What a wind field's per-frame update reads.
pub struct WindInput<'a> {
    /// The cluster grid whose corners carry the field: a block field's innermost level.
    pub grid: &'a ClusterGrid,
    /// Its nested levels: 1 (a stored field's one grid), or a block field's `WIND_LEVELS`, level
    /// l at 2^l times the grid's spacing about the same centre (`field_gpu::wind_level`).
    pub levels: u32,
    /// The forces.
    pub wind: &'a Wind,
    /// Where point sources are attenuated.
    pub attenuation: Attenuation,
    /// Simulation time in seconds.
    pub time: f64,
    /// World (x, z) the GPU's positions are relative to, exact in f64 (a block field's origin O;
    /// zero for a stored field): the corners lie at `origin` + their grid position.
    pub origin: DVec2,
    /// The thesis' path (`--brute-force`): the CPU writes the corners; otherwise the field's
    /// passes do.
    pub cpu_corners: bool,
    /// The camera's world position (m): where a field's camera grid centres.
    pub camera: glam::DVec3,
    /// The simulation's fixed step (s): a stateful field steps by it once a frame.
    pub dt: f32,
    /// A block field's ground, the ground a field's heights are measured from (`None`: a stored
    /// field, measured from y = 0).
    pub ground: Option<&'a crate::scene::FieldGround>,
}

/// What a wind field's passes are built with: the frames' buffers they write and read.
pub struct WindSetup<'a> {
    /// Per frame in flight: its corners (written) and its emitters (read).
    pub frames: &'a [(vk::DescriptorBufferInfo, vk::DescriptorBufferInfo)],
    /// Corners over every level.
    pub corners: u32,
    /// The scene pipelines' specialization constants.
    pub constants: &'a Specialization,
}

/// A wind field.
pub trait WindField {
    /// Name in reports.
    fn name(&self) -> &'static str;

    /// Write this frame's CPU part into `forces` (the frame's host-visible buffers, visible to
    /// the GPU at submission) and whatever the field's passes read this frame.
    fn update(&self, forces: &mut FrameForces, input: &WindInput);

    /// The compute passes that produce the field this frame, before every reader (none on the
    /// thesis' CPU path).
    fn passes(&self, device: &Device, setup: &WindSetup) -> Result<Vec<Box<dyn Pass>>>;

    /// The resources the passes `passes` built last use that the graph must know, with the
    /// access they were left in (the fluid's images, new and untouched).
    fn tracked(&self) -> Vec<(crate::vk::Resource, Vec<crate::vk::Access>)> {
        Vec::new()
    }

    /// Whether the field keeps state from step to step (the fluid's grid): the headless commands
    /// then step it from t = 0 to the frame asked for (`app::warm_up`).
    fn stateful(&self) -> bool {
        false
    }

    /// A stateful field's grid as its passes leave it each frame (an RGBA32F 3-D image in
    /// GENERAL, its extent and the toroidal base of its window), for a read-back.
    fn state(&self) -> Option<(vk::Image, vk::Extent3D, glam::UVec3)> {
        None
    }
}
