//! The uniform block every pass reads (`FrameUniforms`, std140, mirrored in
//! `shaders/common/common.glsl`), and the light and atmosphere it carries.

use bytemuck::{Pod, Zeroable};
use glam::{IVec4, Mat4, UVec4, Vec3, Vec4};

/// Per-frame constants, std140 (`shaders/common/common.glsl`, struct `FrameUniforms`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// World → clip.
    pub view_proj: Mat4,
    /// xyz eye position, w simulation time in seconds.
    pub camera_position: Vec4,
    /// xyz unit vector towards the sun.
    pub sun_direction: Vec4,
    /// rgb linear sky colour, w fog density per metre.
    pub sky_color: Vec4,
    /// A stored terrain: x grid origin, y cell size (read by the CPU's cull mirror); a block
    /// field: y the innermost wind level's cluster edge. The ground itself is `ground`.
    pub terrain: Vec4,
    /// x segments, y blade count, z the far field's band start (m, f32 bits; 0: none,
    /// `render::far_field`), w with a far field the view distance (m, f32 bits). (The blade geometry and
    /// the sRGB encoding are specialization constants, `render::specialization`.)
    pub params: UVec4,
    /// x point sources, y colliders (their emitters after the sources'), z cluster corners per
    /// side, w the wind's levels (`SceneGpu::wind_levels`): the wind field's counts. (A blade response's parameters are in its own
    /// uniform block, `render::animation::response`.)
    pub wind_counts: UVec4,
    /// World → clip of the culling camera (the view's, or a frozen one).
    pub cull_view_proj: Mat4,
    /// xyz culling camera position, w pixels per metre at 1 m (viewport height / (2 tan(fov_y / 2))).
    pub cull_eye: Vec4,
    /// x blade range (m, `Culling::blade_range`), y full-density distance (m), z pixels per segment, w largest widening
    /// (the LOD scale applied).
    pub lod: Vec4,
    /// x tile grid origin, y tile edge (m).
    pub tile_grid: Vec4,
    /// x tiles per side, y ring slots, z and w the centre tile.
    pub cull_tiles: UVec4,
    /// x LOD buckets, y their segment counts minus 1 (4 bits each), z `CULL_*` / `LOD_*` bits.
    pub cull_lod: UVec4,
    /// Block fields: per relief wave, the wave vector, the amplitude and the phase.
    pub relief_waves: [Vec4; 8],
    /// Block fields: sin and cos of each wave's phase at the origin O, two waves per vector.
    pub relief_phases: [Vec4; 4],
    /// Block fields: xy O's cell, z cells per side of a bounded field (0: unbounded).
    pub field_cells: IVec4,
    /// Block fields: x block edge, y relief slope bound, zw the force corners' origin relative to O.
    pub field: Vec4,
    /// The ground's clipmap (`render::ground`): x cells per side of a level, z levels; yw unused.
    pub ground: UVec4,
    /// Block fields: per relief wave its whole periods in the world's (m, n), two waves per vector.
    pub relief_cycles: [IVec4; 4],
    /// Per clipmap level: xy its window's first vertex relative to O, z its cell edge, w the run
    /// (m) its texels' rise is given over (`render::ground`).
    pub ground_levels: [Vec4; 8],
    /// Per clipmap level: xy its window's toroidal base (`render::camera_grid`), zw the source's
    /// (the relief's: the window's first vertex in half-metres on the world's period).
    pub ground_windows: [IVec4; 8],
    /// The cull's draw classes (`render::draw_class::ClassLayout`): x buckets of every class, y
    /// buckets drawn far to near (a bit each), z buckets drawn a row per visible tile, w further
    /// classes.
    pub cull_classes: UVec4,
    /// The first bucket of further class 1, 2, 3, 4.
    pub cull_class_first: UVec4,
    /// Per bucket of a further class: its instance's index count and first index, two buckets
    /// per vector.
    pub cull_bucket_draws: [UVec4; 4],
    /// xyz the point the far field's band is measured from (`render::far_rings::BandEye`: the
    /// culling camera on a leash), relative to O for a block field; w the leash (m).
    pub band_eye: Vec4,
    /// x verdicts the cull's `cull_results` holds, y the most candidates a draw-class set's own
    /// source adds to a ring slot (`render::draw_class::CandidateSource`; 0: none).
    pub cull_room: UVec4,
}

impl FrameUniforms {
    /// These uniforms seen through `camera` instead (a bake's own view, `Renderer::frame_instance`):
    /// its view-projection for the view and the cull, its eye for both; the light, the time and
    /// the scene's terms as they are.
    pub fn with_orthographic(&self, camera: &crate::scene::OrthographicCamera) -> Self {
        let view_proj = camera.view_projection();
        let eye = camera.position.extend(self.camera_position.w);
        Self {
            view_proj,
            camera_position: eye,
            cull_view_proj: view_proj,
            cull_eye: camera.position.extend(self.cull_eye.w),
            ..*self
        }
    }
}

const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 992);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, cull_view_proj) == 160);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, cull_lod) == 288);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, camera_position) == 64);
const _: () = assert!(std::mem::offset_of!(FrameUniforms, params) == 128);

/// Light and atmosphere of the scene.
pub mod look {
    use super::*;

    /// Unit vector towards the sun: low, ahead-left of the default camera, so much of the field is
    /// back-lit and shows the translucency term.
    pub fn sun_direction() -> Vec3 {
        Vec3::new(-0.45, 0.5, -0.75).normalize()
    }

    /// Linear sky colour.
    pub const SKY: Vec3 = Vec3::new(0.42, 0.60, 0.86);
    /// Fog density per metre: at 1 km a surface keeps e^-1 = 37 % of its colour, so the far field
    /// is seen to the horizon (issue #37 asks ≥ 30 %; 0.012 until 2026-12-07 hid all past 400 m).
    pub const FOG_DENSITY: f32 = 0.001;

    /// sRGB transfer of one linear channel as the shaders encode it (`encode_output` of
    /// lighting.glsl: the curve by Ian Taylor's three-square-root fit), so the clear colour
    /// matches the fogged fragments.
    pub fn encode_srgb(linear: f32) -> f32 {
        let c = linear.clamp(0.0, 1.0);
        if c < 0.003_130_8 {
            c * 12.92
        } else {
            let (s1, s2, s3) = (c.sqrt(), c.sqrt().sqrt(), c.sqrt().sqrt().sqrt());
            0.585_122_4 * s1 + 0.783_140_36 * s2 - 0.368_262_74 * s3
        }
    }

    /// The exact sRGB transfer (IEC 61966-2-1) `encode_srgb` approximates.
    pub fn encode_srgb_exact(linear: f32) -> f32 {
        let c = linear.clamp(0.0, 1.0);
        if c < 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    }
}
