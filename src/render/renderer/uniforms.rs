//! The frame's uniforms (`FrameUniforms`) as the renderer fills them for a camera, a time and a
//! target's extent: the view, the light and the fog, the cull's and the block field's parts, and
//! the wind field's counts.

use ash::vk;
use glam::{IVec2, UVec4, Vec4};

use super::Renderer;
use crate::render::animation;
use crate::render::field_gpu::{self, Origin};
use crate::render::frame::{look, FrameUniforms};
use crate::render::gpu_constants as gpu;
use crate::render::occlusion;
use crate::scene::camera::near_plane;
use crate::scene::Camera;

/// Steps of a fixed-point depth format (2^bits − 1), `None` for a float one: what the near plane
/// is derived from (`scene::camera::near_plane`).
fn depth_steps(format: vk::Format) -> Option<u32> {
    match format {
        vk::Format::D16_UNORM | vk::Format::D16_UNORM_S8_UINT => Some(u32::from(u16::MAX)),
        vk::Format::X8_D24_UNORM_PACK32 | vk::Format::D24_UNORM_S8_UINT => Some((1 << 24) - 1),
        _ => None,
    }
}

impl Renderer {
    /// Entries of the cull's visible list a frame may fill (`scene_gpu::visible_limit`).
    pub(super) fn visible_limit(&self) -> u32 {
        // Per frame: from the records' own flag, not the response's `blade_input` (which builds
        // its resource lists).
        let per_blade = self.poses.as_ref().filter(|poses| poses.written).map(|poses| poses.level_records);
        crate::render::scene_gpu::visible_limit(&self.device, self.scene_gpu(), self.settings.segments, per_blade)
    }

    /// The uniforms of a frame seen from `camera` at simulation time `time` into `extent`.
    pub fn frame_uniforms(&self, camera: &Camera, time: f32, extent: vk::Extent2D) -> FrameUniforms {
        let scene = self.scene_gpu();
        // A block field: every position relative to the origin under the camera.
        let origin = scene.field.as_ref().map(|_| Origin::under(camera));
        let relative = |c: &Camera| origin.map_or(*c, |o| o.relative(c));
        let camera = &relative(camera);
        let aspect = extent.width as f32 / extent.height as f32;
        let culling = &self.settings.culling;
        let near = near_plane(depth_steps(self.device.depth_format), culling.view_distance);
        let (sources, colliders) = animation::emitter_counts(&self.animation.wind);
        let far = self.far_band();
        let mut uniforms = FrameUniforms {
            view_proj: camera.view_projection_near(aspect, near),
            camera_position: camera.position.extend(time),
            sun_direction: look::sun_direction().extend(0.0),
            sky_color: look::SKY.extend(self.settings.fog_density),
            terrain: Vec4::new(scene.terrain_origin, scene.terrain_cell_size, 0.0, 0.0),
            params: UVec4::new(self.settings.segments, scene.blade_count, far.0.to_bits(), far.1.to_bits()),
            wind_counts: UVec4::new(sources, colliders, scene.grid.corners_per_side(), scene.wind_levels),
            cull_lod: UVec4::new(0, 0, 0, self.visible_limit()),
            cull_room: UVec4::new(scene.verdict_capacity, self.builders.classes.source_room(), 0, 0),
            ..bytemuck::Zeroable::zeroed()
        };
        let cull_camera = self.cull_camera.as_ref().map_or(*camera, relative);
        let frozen = self.cull_camera.is_some();
        culling.fill_uniforms(&mut uniforms, &scene.tile_grid, &cull_camera, frozen, (aspect, near), extent.height);
        // Looking down more steeply than the ground can rise, the terrain hides nothing: no
        // occlusion test, and no depth pyramid, this frame (`render::occlusion`).
        if occlusion::terrain_cannot_occlude(uniforms.cull_view_proj, scene.ground_slope) {
            uniforms.cull_lod.z &= !gpu::CULL_OCCLUSION;
        }
        // The band's eye (`far_rings::BandEye`), the culling camera's own before any frame.
        let band = self.band_eye.at().map_or(cull_camera.position, |at| {
            let o = origin.map_or(glam::DVec2::ZERO, |o| o.world);
            glam::DVec3::new(at.x - o.x, at.y, at.z - o.y).as_vec3()
        });
        uniforms.band_eye = band.extend(self.band_leash());
        // Every draw class's buckets (`build_graph` placed them without error).
        if let Ok(layout) = self.class_layout() {
            layout.fill_uniforms(&mut uniforms);
        }
        let distances = (culling.view_distance, culling.blade_range());
        scene.ground.source.fill_uniforms(&mut uniforms, origin.map_or(IVec2::ZERO, |o| o.cell), distances);
        if let (Some(field), Some(origin)) = (&scene.field, &origin) {
            field_gpu::fill_uniforms(&mut uniforms, field, origin, &scene.grid, distances.1);
            // A longer blade range set live (the viewer) than the one the cull's buffers were
            // made for: the rings stop where the buffers do.
            uniforms.cull_tiles.y = uniforms.cull_tiles.y.min(scene.slot_capacity);
        }
        uniforms
    }

    /// Where the blades start to thin out for the far field (m; 0: no far field) and where a block
    /// field's ground ends (m; 0: stored blades or the floor): the cull's band dither
    /// (`shaders/cull/cull.glsl`) and the haze of the view's last fifth (`horizon_haze` of
    /// `shaders/common/lighting.glsl`, on the ground, the blades, the flowers and the far field),
    /// the frame's `params.z` and `params.w`.
    pub(super) fn far_band(&self) -> (f32, f32) {
        let field = self.scene.as_ref().is_some_and(|scene| scene.field.is_some());
        if !field || self.settings.floor {
            return (0.0, 0.0);
        }
        let culling = &self.settings.culling;
        culling.far_rings().map_or((0.0, culling.view_distance), |rings| (rings.band_start, rings.view_distance))
    }

    /// How far the far field's band's eye trails the culling camera (m; 0 without a far field).
    pub(super) fn band_leash(&self) -> f32 {
        let culling = &self.settings.culling;
        match self.far_band().0 > 0.0 {
            true => culling.far_rings().map_or(0.0, |rings| rings.leash(culling.band_leash)),
            false => 0.0,
        }
    }

    /// The fog's density per metre of the next frames (`--fog`, the viewer's slider): uniforms only.
    pub fn set_fog_density(&mut self, density: f32) {
        self.settings.fog_density = density;
    }
}
