//! The renderer's side of the wind field (`render::wind`): each frame's CPU update, and whether
//! the field's passes run.

use super::Renderer;
use crate::render::animation::BladeInput;
use crate::render::field_gpu::Origin;
use crate::render::wind::WindInput;
use crate::scene::Camera;

impl Renderer {
    /// The wind field's per-frame CPU update into the frame's host-visible buffers (the emitters,
    /// and with `--brute-force` the thesis' corner forces, 3.2.2; with the cull its pass's
    /// parameters); they are visible to the GPU at submission. Then the pressed map's sweeps.
    pub(super) fn update_wind(&mut self, slot: usize, camera: &Camera, time: f32) {
        let origin = self.origin_of(camera);
        let scene = self.scene.as_ref().expect("uploaded");
        let input = WindInput {
            grid: &scene.grid,
            levels: scene.wind_levels,
            wind: &self.animation.wind,
            attenuation: self.animation.attenuation,
            time: f64::from(time),
            origin,
            cpu_corners: !self.settings.culling.enabled,
            camera: camera.position.as_dvec3(),
            dt: self.time_step,
            ground: scene.field.as_ref().map(|f| &f.ground),
        };
        self.wind.update(&mut self.forces[slot], &input);
        if let Some(map) = &self.pressed {
            let eye = camera.position.as_dvec3();
            map.update(&self.animation.wind, self.animation.pressed, origin, f64::from(time), eye);
        }
    }

    /// World (x, z) the GPU's positions are relative to under `camera`: a block field's origin O
    /// (`field_gpu::Origin`), zero for a stored field.
    pub(super) fn origin_of(&self, camera: &Camera) -> glam::DVec2 {
        let scene = self.scene.as_ref().expect("uploaded");
        scene.field.as_ref().map_or(glam::DVec2::ZERO, |_| Origin::under(camera).world)
    }

    /// Whether the blade response or the wind field (when its passes run) keeps state from step
    /// to step, or interaction patches may (colliders, and a response that writes pose records):
    /// reaching a time then takes steps before it (`warm_up_from`, `app::warm_up`).
    pub fn stateful(&self) -> bool {
        self.warm_up_from(0).is_some()
    }

    /// The step a warm-up to `first` starts from: 0 when the response or the wind field keeps
    /// state; `patches::WARM_UP_S` before `first` when only interaction patches do (a patch hands
    /// back within `TIMEOUT_S + BLEND_S` of its last contact, and what it holds longer, under a
    /// collider at rest, is its chain's settling under it); `None` when nothing keeps state.
    pub fn warm_up_from(&self, first: u64) -> Option<u64> {
        let response = self.response.as_deref();
        if response.is_some_and(|r| r.stateful()) || (self.wind.stateful() && self.wind_passes_run()) {
            return Some(0);
        }
        let posed = response.is_some_and(|r| r.blade_input().pose_records());
        let patched = posed && self.pressed.is_some() && !self.animation.wind.colliders.is_empty();
        let window = self.animation.clock.steps_to(f64::from(crate::render::animation::patches::WARM_UP_S));
        patched.then(|| first.saturating_sub(window))
    }

    /// Whether the wind field's passes run: with the cull, when something samples the wind (a
    /// response that poses blades, the bounds view's corner colours or the wind view's arrows).
    /// Brute force keeps the thesis' CPU corners.
    pub(super) fn wind_passes_run(&self) -> bool {
        let settings = &self.settings;
        let posed = self.response.as_deref().is_some_and(|r| !matches!(r.blade_input(), BladeInput::Neutral));
        settings.culling.enabled && !settings.floor && (posed || settings.debug_bounds || settings.debug_wind)
    }
}
