//! What animates the blades. The settings a renderer is built with, the thesis' CPU mirror of
//! the wind at cluster corners (3.2.2, what `--brute-force` writes; `render::wind` evaluates it
//! on the GPU with the cull) and of a blade's interpolated wind and force, the fixed time step
//! (`clock`), and the seam every blade response plugs into (`response::BladeResponse`): today's
//! static blades (`still`) and keyframes from a texture or a uniform array, per vertex or per
//! blade (`keyframed`, thesis ch. 3–4), with their GPU tables (`keyframe_gpu`) and the
//! per-blade pose pass (`pose_pass`), writing the renderer's pose records (`poses`).

pub mod blade_state;
pub mod chain;
pub mod clock;
pub mod collider_bins;
pub mod inertial;
pub mod keyframe_gpu;
pub mod keyframed;
pub mod patch_pass;
pub mod patches;
pub mod pose_pass;
pub mod poses;
pub mod pressed;
pub mod push_out;
pub mod response;
pub mod sine;
pub mod still;
pub mod verlet;
pub mod virtual_blades;
pub mod virtual_inertial;

pub use keyframe_gpu::{texture_format, KeyframeTexture, KeyframeUniforms};
pub use response::{BladeInput, BladeResponse};

use glam::{Vec2, Vec3, Vec4};

use crate::keyframes::encoding::{Encoding, Packing};
use crate::keyframes::{Representation, Smoothing};
use crate::render::gpu_constants;
use crate::scene::clusters::ClusterGrid;
use crate::vk::Device;
use crate::wind::{Attenuation, Wind, KEYFRAME_WIND_SCALE};

/// Build the response `context.animation.mode` names (the CLI's `--mode`): the library's
/// `response::BuildResponse`.
pub fn build_response(
    device: &Device,
    context: &response::ResponseContext,
) -> crate::error::Result<Box<dyn BladeResponse>> {
    Ok(match context.animation.mode {
        Mode::Static => Box::new(still::StaticResponse),
        Mode::Texture | Mode::Uniform => {
            Box::new(keyframed::KeyframeResponse::new(device, context.animation, context.segments)?)
        }
        Mode::Sine(phase) => {
            let direction = context.animation.wind.global.map_or(0.0, |g| g.direction_deg);
            Box::new(sine::SineResponse::new(phase, direction))
        }
        Mode::Verlet => Box::new(verlet::VerletResponse::new(device, context.scene, context.animation.verlet)?),
        Mode::Inertial => Box::new(inertial::InertialResponse::new(device, context.scene, context.animation.chain)?),
        Mode::VirtualInertial => {
            Box::new(virtual_inertial::VirtualInertialResponse::new(device, context.scene, context.animation.chain)?)
        }
    })
}

/// How blades are posed: the blade response (`--animation`), and for keyframes where their table
/// lives (`--mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Neutral Bézier blades, no forces.
    Static,
    /// Keyframes sampled from a texture in the vertex shader (thesis 4.4.1).
    #[default]
    Texture,
    /// Keyframes in a uniform array, two 16-bit values per 32-bit word (thesis 4.4.2).
    Uniform,
    /// Pelzer's sine animation (§7.4), its phase per object, per vertex or per cluster (`sine`).
    Sine(sine::SinePhase),
    /// Zhang Xia's Verlet blades (§3.2.3–3.2.5), stateful (`verlet`).
    Verlet,
    /// Belyaev's inertial segment chains (§3.1), stateful (`inertial`).
    Inertial,
    /// Belyaev's virtually-inertial blades (§3.3): virtual chains at the wind corners, the drawn
    /// blades at their static equilibrium under them (`virtual_inertial`).
    VirtualInertial,
}

impl Mode {
    /// How the blade class draws for this mode: a row per visible tile for the sine per cluster
    /// (Pelzer's one draw per cluster), else as the settings say (`Culling::rows`).
    pub fn draw_rows(self) -> Option<crate::render::draw_rows::DrawRows> {
        (self == Mode::Sine(sine::SinePhase::Cluster)).then_some(crate::render::draw_rows::DrawRows::PerTile)
    }

    /// Index used by the shaders.
    pub fn code(self) -> u32 {
        match self {
            Mode::Static | Mode::Sine(_) | Mode::Verlet | Mode::Inertial | Mode::VirtualInertial => {
                gpu_constants::MODE_STATIC
            }
            Mode::Texture => gpu_constants::MODE_TEXTURE,
            Mode::Uniform => gpu_constants::MODE_UNIFORM,
        }
    }
}

/// Where the per-blade part of the animation runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Eval {
    /// In the vertex shader, for every vertex (as the thesis did on shader model 3).
    #[default]
    Vertex,
    /// Once per blade in a compute pass that evaluates every level (point, tangent, twist) into
    /// records the vertex shader reads (`shaders/animation/blade_pose.comp`).
    Blade,
}

impl Eval {
    /// The default placement: once per drawn blade when the cull runs (the blade-pose pass then
    /// covers only its visible list, and the vertex shader no longer repeats the keyframe
    /// selection at every vertex: 1M blades, default camera, 213 → 175 ms on lavapipe), per
    /// vertex with brute force (the thesis' path, which its benchmark measures).
    pub fn default_for(culled: bool) -> Self {
        if culled {
            Eval::Blade
        } else {
            Eval::Vertex
        }
    }
}

/// Everything about the animation a renderer is built with.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationSettings {
    /// Static or keyframed.
    pub mode: Mode,
    /// Poses over the full circle (a quarter is stored).
    pub poses: u32,
    /// In-between poses.
    pub smoothing: Smoothing,
    /// Keyframe texture encoding.
    pub encoding: Encoding,
    /// Uniform-array packing.
    pub packing: Packing,
    /// Per vertex or per blade.
    pub eval: Eval,
    /// Vertex levels (thesis) or Bézier control points.
    pub representation: Representation,
    /// Where source magnitudes are attenuated.
    pub attenuation: Attenuation,
    /// Cluster edge in metres.
    pub cluster_size: f32,
    /// The forces.
    pub wind: Wind,
    /// The wind field that carries them to the blades (`--wind-field`).
    pub wind_field: crate::wind::FieldKind,
    /// The fluid wind's grid (`--fluid-grid`, `--fluid-cell`), when `wind_field` is the fluid.
    pub fluid: crate::wind::FluidGrid,
    /// The simulation's fixed time step (`--dt`).
    pub clock: clock::StepClock,
    /// The Verlet blades' constants (`--stiffness`, `--damping`).
    pub verlet: verlet::VerletParams,
    /// The inertial chains' constants (`--stiffness`, `--damping`).
    pub chain: chain::ChainParams,
    /// The pressed map's recovery and regrowth (`--recovery-s`, `--regrow-s`).
    pub pressed: pressed::PressedParams,
}

impl Default for AnimationSettings {
    fn default() -> Self {
        Self {
            mode: Mode::Texture,
            poses: 1000,
            smoothing: Smoothing::Nearest,
            encoding: Encoding::Unorm16,
            packing: Packing::Snorm,
            eval: Eval::Vertex,
            representation: Representation::Vertex,
            attenuation: Attenuation::Cluster,
            cluster_size: 1.0,
            wind: Wind::default(),
            wind_field: crate::wind::FieldKind::Analytic,
            fluid: crate::wind::FluidGrid::default(),
            clock: clock::StepClock::default(),
            verlet: verlet::VerletParams::default(),
            chain: chain::ChainParams::default(),
            pressed: pressed::PressedParams::default(),
        }
    }
}

impl AnimationSettings {
    /// What makes the blade pass read pose records, as an error names it (`--eval blade` for
    /// keyframes, a sine variant always); `None` when the blades are posed per vertex or neutral.
    pub fn pose_writer(&self) -> Option<&'static str> {
        match self.mode {
            Mode::Static => None,
            Mode::Texture | Mode::Uniform => (self.eval == Eval::Blade).then_some("--eval blade"),
            Mode::Sine(sine::SinePhase::Object) => Some("--animation sine-object"),
            Mode::Sine(sine::SinePhase::Vertex) => Some("--animation sine-vertex"),
            Mode::Sine(sine::SinePhase::Cluster) => Some("--animation sine-cluster"),
            Mode::Verlet => Some("--animation verlet"),
            Mode::Inertial => Some("--animation inertial"),
            Mode::VirtualInertial => Some("--animation virtual-inertial"),
        }
    }
}

/// Point sources a renderer can hold.
pub const MAX_SOURCES: usize = crate::render::gpu_constants::MAX_SOURCES as usize;
/// Colliders a renderer can hold, apart from the sources (issue #34).
pub const MAX_COLLIDERS: usize = crate::render::gpu_constants::MAX_COLLIDERS as usize;

/// The emitter buffers' elements (vec4) before the collider bins: a point source takes one, a
/// collider two (centre and radii).
pub const EMITTER_ELEMENTS: usize = crate::render::gpu_constants::EMITTER_ELEMENTS as usize;
const _: () = assert!(EMITTER_ELEMENTS == MAX_SOURCES + 2 * MAX_COLLIDERS);

/// The corner winds of a frame on the CPU, the thesis' path (`--brute-force`): (vx, vy, vz,
/// calm-area exposure) per corner, in m/s (`wind::KEYFRAME_WIND_SCALE` times the keyframe force).
pub fn corner_forces(grid: &ClusterGrid, wind: &Wind, time: f32, attenuation: Attenuation) -> Vec<Vec4> {
    corner_forces_at(grid, Vec2::ZERO, wind, time, attenuation)
}

/// The corner winds of a grid whose corners lie at `origin` + their grid position (a block
/// field's grid, relative to its origin O, follows the camera), in f32 as the thesis computed
/// them: the CPU mirror of `shaders/wind/analytic_corners.comp`.
pub fn corner_forces_at(
    grid: &ClusterGrid,
    origin: Vec2,
    wind: &Wind,
    time: f32,
    attenuation: Attenuation,
) -> Vec<Vec4> {
    (0..grid.corner_count())
        .map(|i| {
            let p = origin + grid.corner_position(i);
            let f = wind.corner_force(p, time, attenuation);
            // A non-finite force (overflowing eq. 4.1) would select an undefined pose: none.
            let f = if f.is_finite() { f } else { Vec2::ZERO } * KEYFRAME_WIND_SCALE;
            Vec4::new(f.x, 0.0, f.y, wind.exposure(p))
        })
        .collect()
}

/// The emitters of a frame: point sources at their positions at `time` as (x, z, power, sigma),
/// then each collider as two elements, its centre at `time` (x, y, z, 0) and its radii (x, y, z, 0),
/// then from `collider_bins::COLLIDER_BINS` the colliders binned over the ground; the shader reads
/// only as many as the uniforms count.
pub fn emitters(wind: &Wind, time: f32) -> Vec<Vec4> {
    let mut out: Vec<Vec4> = wind
        .sources
        .iter()
        .map(|s| {
            let p = s.position_at(time);
            Vec4::new(p.x, p.y, s.power, s.sigma)
        })
        .chain(wind.colliders.iter().flat_map(|c| [c.center_at(time).extend(0.0), c.radii.extend(0.0)]))
        .collect();
    collider_bins::append(&mut out, wind.sources.len());
    out
}

/// The wind at a blade as `shaders/wind/wind_field.glsl` samples it (`wind_at_blade`), on the
/// CPU: the corners' wind weighted (eq. 3.6/3.8), plus with delayed attenuation every source at
/// the blade; velocity (x, z) in m/s. The reference for GPU read-back tests.
pub fn blade_wind(
    grid: &ClusterGrid,
    cluster: &crate::scene::clusters::BladeCluster,
    corners: &[Vec4],
    emitters: &[Vec4],
    sources: usize,
    attenuation: Attenuation,
    root: Vec2,
) -> Vec2 {
    let n = grid.corners_per_side() as usize;
    let w = cluster.unpacked_weights();
    let c = cluster.corner as usize;
    let f = corners[c] * w[0] + corners[c + 1] * w[1] + corners[c + n] * w[2] + corners[c + n + 1] * w[3];
    let mut wind = Vec2::new(f.x, f.z);
    if attenuation == Attenuation::Blade {
        let scale = KEYFRAME_WIND_SCALE;
        for e in &emitters[..sources] {
            wind += f.w * (crate::wind::PointSource::force_from(Vec2::new(e.x, e.y), e.z, e.w, root) * scale);
        }
    }
    wind
}

/// A block field's wind at `root` (relative to O) as `levels_wind` of
/// `shaders/wind/wind_field.glsl` samples it, on the CPU: `corners` holds the field's levels (at
/// most `WIND_LEVELS`) of `field_gpu::wind_level(cluster_size, l)` one after the other (as the
/// wind field writes them); the finest level that holds the point, bilinearly (eq. 3.6–3.8, unquantised weights),
/// blended into the next over the outer quarter of its half-extent. Velocity (x, y, z) in m/s and
/// the exposure. The reference for GPU read-back tests.
pub fn levels_wind(cluster_size: f32, corners: &[Vec4], root: Vec2) -> Vec4 {
    use crate::render::gpu_constants::WIND_LEVEL_CLUSTERS;
    let n = WIND_LEVEL_CLUSTERS + 1;
    let levels = (corners.len() / (n * n) as usize).max(1) as u32;
    let sample = |level: u32| {
        let size = cluster_size * (1u32 << level) as f32;
        let first = 0.5 * crate::scene::field::BLOCK_SIZE - 0.5 * WIND_LEVEL_CLUSTERS as f32 * size;
        let g = ((root - Vec2::splat(first)) / size).clamp(Vec2::ZERO, Vec2::splat((n - 1) as f32));
        let c = g.as_uvec2().min(glam::UVec2::splat(n - 2));
        let f = g - c.as_vec2();
        let w = [(1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y];
        let i = (level * n * n + c.y * n + c.x) as usize;
        let n = n as usize;
        corners[i] * w[0] + corners[i + 1] * w[1] + corners[i + n] * w[2] + corners[i + n + 1] * w[3]
    };
    let half0 = 0.5 * WIND_LEVEL_CLUSTERS as f32 * cluster_size;
    let from_centre = (root - Vec2::splat(0.5 * crate::scene::field::BLOCK_SIZE)).abs();
    let ratio = from_centre.max_element() / half0;
    let level = if ratio <= 1.0 { 0 } else { (ratio.log2().ceil() as u32).min(levels - 1) };
    let blend = ((ratio / (1u32 << level) as f32 - 0.75) * 4.0).clamp(0.0, 1.0);
    let f = sample(level);
    if level + 1 < levels && blend > 0.0 {
        f.lerp(sample(level + 1), blend)
    } else {
        f
    }
}

/// The keyframes' force for `blade` (`blade_force` of `shaders/animation/forces.glsl`): its wind
/// (`blade_wind`) in keyframe units through the fixed scale `wind::KEYFRAME_WIND_SCALE`, plus the
/// reach-weighted force of every collider in `emitters` (after the `sources`, two elements each,
/// `wind::Collider::blade_force`), under either attenuation.
pub fn blade_force(
    grid: &ClusterGrid,
    cluster: &crate::scene::clusters::BladeCluster,
    corners: &[Vec4],
    emitters: &[Vec4],
    sources: usize,
    attenuation: Attenuation,
    blade: &crate::scene::BladeInstance,
) -> Vec2 {
    let root = Vec3::from(blade.position);
    let wind = blade_wind(grid, cluster, corners, emitters, sources, attenuation, Vec2::new(root.x, root.z));
    let mut force = wind * (1.0 / KEYFRAME_WIND_SCALE);
    // The colliders: the pairs after the sources, before the padding (a collider's radii are above 0).
    let colliders = emitters[sources..collider_bins::COLLIDER_BINS.min(emitters.len())].chunks_exact(2);
    for pair in colliders.take_while(|pair| pair[1] != Vec4::ZERO) {
        let push = crate::wind::Collider::blade_force(pair[0].truncate(), pair[1].truncate(), root, blade.height);
        // Only where it pushes, as the shader: -0 + 0 would be +0.
        if push != Vec2::ZERO {
            force += push;
        }
    }
    force
}

/// Sources and colliders the shaders read: the first `MAX_SOURCES` and `MAX_COLLIDERS` of them,
/// sources first (the emitter buffers hold `EMITTER_ELEMENTS`: a source takes one, a collider two).
pub fn emitter_counts(wind: &crate::wind::Wind) -> (u32, u32) {
    let sources = wind.sources.len().min(MAX_SOURCES);
    let colliders = wind.colliders.len().min(MAX_COLLIDERS);
    (sources as u32, colliders as u32)
}
