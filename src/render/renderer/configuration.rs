//! What the renderer was built with, and what a caller may change between frames: the settings
//! and animation, the wind (sources, colliders and cuts), the LOD scale and a frozen culling camera.

use super::Renderer;
use crate::render::animation::AnimationSettings;
use crate::render::passes::{BladePass, TerrainPass};
use crate::render::RenderSettings;
use crate::scene::Camera;

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

    /// The forces, editable between frames (they are uploaded per frame). At most
    /// `MAX_SOURCES` sources and `MAX_COLLIDERS` colliders are used; extra ones are ignored.
    pub fn wind_mut(&mut self) -> &mut crate::wind::Wind {
        &mut self.animation.wind
    }
}
