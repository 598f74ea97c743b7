//! What the renderer was built with, and what a caller may change between frames: the settings
//! and animation, the wind (sources, colliders and cuts), the LOD scale and a frozen culling camera;
//! and what a rebuild can take.

use ash::vk;

use super::Renderer;
use crate::error::{Error, Result};
use crate::render::animation::AnimationSettings;
use crate::render::passes::{BladePass, TerrainPass};
use crate::render::settings::{check_field, check_submission, polygon_mode};
use crate::render::{msaa, RenderSettings};
use crate::scene::{Camera, Scene};

impl Renderer {
    /// The settings the renderer was built with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The passes of a frame, in order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        self.graph.pass_names()
    }

    /// Number of blades drawn.
    pub fn blade_count(&self) -> u32 {
        self.scene_gpu().blade_count
    }

    /// Triangles of one frame: (blades, terrain).
    pub fn triangles(&self) -> (u64, u64) {
        let scene = self.scene_gpu();
        (BladePass::triangles(scene, self.settings.segments), TerrainPass::triangles(scene))
    }

    /// The LOD scale of the next frames (`--budget-ms` sets it each frame): uniforms only.
    pub fn set_lod_scale(&mut self, scale: f32) {
        self.settings.culling.lod_scale = scale;
    }
    /// Freeze the culling camera at `camera` (`None`: the view's camera again): fly out and look.
    pub fn set_cull_camera(&mut self, camera: Option<Camera>) {
        self.cull_camera = camera;
    }
    /// The frozen culling camera, if any.
    pub fn cull_camera(&self) -> Option<Camera> {
        self.cull_camera
    }

    /// The animation the renderer was built with.
    pub fn animation(&self) -> &AnimationSettings {
        &self.animation
    }

    /// Whether `settings` fit `scene` as `new` uploaded it: the cull's ring slots for the blade
    /// distance and a block field's wind levels for the far field's reach were sized then, and a
    /// rebuild cannot grow them (a longer distance needs a new renderer; the viewer makes one).
    pub fn fits_upload(&self, scene: &Scene, settings: &RenderSettings) -> bool {
        let uploaded = self.scene_gpu();
        let slots = crate::render::scene_gpu::cull_capacity(scene, settings.culling.blade_range()).0;
        let levels = match scene.field {
            Some(_) => {
                let cluster = uploaded.grid.cluster_size;
                crate::render::field_gpu::wind_grid(cluster, settings.culling.wind_reach()).1
            }
            None => uploaded.wind_levels,
        };
        slots <= uploaded.slot_capacity && levels <= uploaded.wind_levels
    }

    /// What `rebuild` can take, and the polygon mode of `settings`: the same frames (in flight,
    /// colour format, statistics, encoding) and cluster grid, settings the device supports, a
    /// block field's rules, and distances the upload holds (`fits_upload`).
    pub(super) fn check_rebuild(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        animation: &AnimationSettings,
    ) -> Result<vk::PolygonMode> {
        let (old, device) = (&self.settings, &self.device);
        let same_frames = (old.frames_in_flight, old.color_format, old.pipeline_statistics, old.encode_srgb)
            == (settings.frames_in_flight, settings.color_format, settings.pipeline_statistics, settings.encode_srgb);
        if !same_frames || animation.cluster_size != self.animation.cluster_size {
            return Err(Error::Internal("rebuild cannot change the frames or the cluster grid".into()));
        }
        let polygon = polygon_mode(device, settings.wireframe)?;
        check_submission(device, settings)?;
        msaa::check(device, &settings.msaa)?;
        if scene.field.is_some() {
            check_field(settings)?;
        }
        if !self.fits_upload(scene, settings) {
            let why = "rebuild cannot grow the cull's rings or the wind's levels: a new renderer";
            return Err(Error::Internal(why.into()));
        }
        Ok(polygon)
    }

    /// The forces, editable between frames (they are uploaded per frame). At most
    /// `MAX_SOURCES` sources and `MAX_COLLIDERS` colliders are used; extra ones are ignored.
    pub fn wind_mut(&mut self) -> &mut crate::wind::Wind {
        &mut self.animation.wind
    }
}
