//! Rebuilding what the viewer draws: the passes on the same scene (a key that changes pipelines),
//! a new renderer on a new scene (a blade count, the slope limit, clumps, flowers), and the line that
//! reports what it now draws. A change the device cannot take is reported and undone.

use super::Viewer;
use crate::error::Result;
use crate::render::animation::AnimationSettings;
use crate::render::culling::Culling;
use crate::render::RenderSettings;
use crate::scene::Scene;

impl Viewer {
    /// The panel's clump size: blades in clumps of `size_m` metres.
    pub(super) fn set_clump_size(&mut self, size_m: f32) -> Result<()> {
        let animation = self.renderer.as_ref().expect("renderer built").animation().clone();
        self.set_clumps(Some(crate::scene::clumps::Clumps { size_m }), self.settings, animation)
    }

    /// The panel's frames in flight: they are the renderer's, so a new one.
    pub(super) fn set_frames_in_flight(&mut self, frames_in_flight: usize) -> Result<()> {
        let animation = self.renderer.as_ref().expect("renderer built").animation().clone();
        let settings = RenderSettings { frames_in_flight, ..self.settings };
        let what = format!("{frames_in_flight} frames in flight");
        if self.replace_renderer(&what, None, settings, animation)? {
            self.options.frames_in_flight = frames_in_flight;
            println!("{what}");
        }
        Ok(())
    }

    /// Rebuild the passes (and the model, if `animation` changed) on the same scene with
    /// `settings`: the old ones are freed behind the frames in flight (the frame ring's deletion
    /// queue), the frames keep running. The LOD scale the frame budget or the overlay set live is
    /// kept. A blade distance or view distance longer than the scene was uploaded for (the
    /// cull's rings, the wind's levels: `Renderer::fits_upload`) makes a new renderer instead. A
    /// change the device cannot take is reported (as `what`) and the previous settings kept.
    /// Returns whether it applied.
    pub(super) fn rebuild_passes(
        &mut self,
        what: &str,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<bool> {
        let renderer = self.renderer.as_ref().expect("renderer built");
        let lod_scale = renderer.settings().culling.lod_scale;
        let settings = RenderSettings { culling: Culling { lod_scale, ..settings.culling }, ..settings };
        if !renderer.fits_upload(&self.scene, &settings) {
            println!(
                "{what}: longer than the scene was uploaded for (the cull's rings, the wind's levels): a new renderer"
            );
            return self.replace_renderer(what, None, settings, animation);
        }
        let checked = self.check_scene(self.scene.blades.len() as u32, &animation);
        let renderer = self.renderer.as_mut().expect("renderer built");
        let applied = match checked.and_then(|()| renderer.rebuild(&self.scene, settings, animation)) {
            Ok(()) => {
                self.settings = settings;
                true
            }
            Err(e) => {
                println!("cannot apply {what}: {e}");
                false
            }
        };
        self.report_rebuild();
        Ok(applied)
    }

    /// A new renderer for `scene` (`None`: the same one), `settings` and `animation`: the old
    /// renderer's frames finish and its memory is freed before the new one is built. One the
    /// device cannot take is reported (as `what`) and the previous scene, settings and animation
    /// built again. Returns whether it applied.
    pub(super) fn replace_renderer(
        &mut self,
        what: &str,
        scene: Option<Scene>,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<bool> {
        let old_animation = self.renderer.as_ref().expect("renderer built").animation().clone();
        let old_settings = self.settings;
        self.renderer = None;
        self.settings = settings;
        let old_scene = scene.map(|scene| std::mem::replace(&mut self.scene, scene));
        if let Err(e) = self.build_renderer(animation) {
            println!("cannot apply {what}: {e}");
            self.settings = old_settings;
            if let Some(scene) = old_scene {
                self.scene = scene;
            }
            return self.build_renderer(old_animation).map(|()| false);
        }
        self.report_rebuild();
        Ok(true)
    }

    /// The options' scene with `blades` stored blades (on the `--heightmap`, under the cover
    /// rules, as at start).
    pub(super) fn scene_with(&self, blades: u32) -> Result<Scene> {
        crate::app::RenderOptions { blades, ..self.options.scene.clone() }.scene()
    }

    /// F4: the slope limit on or off (`--slope-limit`, or `DEFAULT_SLOPE_LIMIT_DEG` when not
    /// given): a new scene (a stored field scattered again) and renderer.
    fn toggle_slope_limit(&mut self, settings: RenderSettings, animation: AnimationSettings) -> Result<()> {
        let landscape = &mut self.options.scene.landscape;
        let before = landscape.slope_limit_deg;
        landscape.slope_limit_deg = match before {
            Some(_) => None,
            None => Some(self.slope_limit_deg),
        };
        let scene = self.scene_with(self.options.scene.blades)?;
        if !self.replace_renderer("'f4'", Some(scene), settings, animation)? {
            self.options.scene.landscape.slope_limit_deg = before;
        }
        Ok(())
    }

    /// F4 the slope limit, F5 clumps, F6 flowers, on or off: a new scene and renderer.
    pub(super) fn toggle_landscape(
        &mut self,
        key: &str,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<()> {
        match key {
            "f4" => self.toggle_slope_limit(settings, animation),
            "f5" => {
                let clumps = match self.options.scene.clumps {
                    Some(_) => None,
                    None => Some(crate::scene::clumps::Clumps { size_m: self.clump_size_m }),
                };
                self.set_clumps(clumps, settings, animation)
            }
            _ => {
                let flowers = match self.options.scene.flowers {
                    Some(_) => None,
                    None => Some(crate::scene::flowers::Flowers { per_m2: self.flowers_per_m2 }),
                };
                self.set_flowers(flowers, settings, animation)
            }
        }
    }

    /// Blades in `clumps` (or none): a new scene (a stored field clumped again) and renderer.
    pub(super) fn set_clumps(
        &mut self,
        clumps: Option<crate::scene::clumps::Clumps>,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<()> {
        if let Some(c) = clumps {
            self.clump_size_m = c.size_m;
        }
        self.replace_scene("clumps", |scene| scene.clumps = clumps, settings, animation)
    }

    /// The panel's flower density: `per_m2` flowers per m².
    pub(super) fn set_flower_density(&mut self, per_m2: f32) -> Result<()> {
        let animation = self.renderer.as_ref().expect("renderer built").animation().clone();
        self.set_flowers(Some(crate::scene::flowers::Flowers { per_m2 }), self.settings, animation)
    }

    /// `flowers` among the blades (or none): a new scene and renderer.
    pub(super) fn set_flowers(
        &mut self,
        flowers: Option<crate::scene::flowers::Flowers>,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<()> {
        if let Some(f) = flowers {
            self.flowers_per_m2 = f.per_m2;
        }
        self.replace_scene("flowers", |scene| scene.flowers = flowers, settings, animation)
    }

    /// A new scene from the options `change` leaves, and a renderer for it; a scene that cannot
    /// be made (flowers denser than the blades) or drawn is reported (as `what`) and the options
    /// restored.
    fn replace_scene(
        &mut self,
        what: &str,
        change: impl FnOnce(&mut crate::app::RenderOptions),
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<()> {
        let before = self.options.scene.clone();
        change(&mut self.options.scene);
        let applied = match self.scene_with(self.options.scene.blades) {
            Ok(scene) => self.replace_renderer(what, Some(scene), settings, animation)?,
            Err(e) => {
                println!("cannot apply {what}: {e}");
                false
            }
        };
        if !applied {
            self.options.scene = before;
        }
        Ok(())
    }

    /// Print what the renderer now draws.
    pub(super) fn report_rebuild(&self) {
        let a = self.renderer.as_ref().expect("built").animation();
        println!(
            "mode {}, smoothing {:?}, eval {:?}, {} wind, {} segments, {} blades, {}{}{}{}{}{}{}{}{}{}",
            if self.settings.floor { "Floor".to_string() } else { format!("{:?}", a.mode) },
            a.smoothing,
            a.eval,
            a.wind_field.name(),
            self.settings.segments,
            self.scene.blades.len(),
            culling_state(&self.settings.culling),
            if self.settings.debug_force { ", force view" } else { "" },
            if self.settings.debug_lod {
                ", LOD view"
            } else if self.settings.debug_tiles {
                ", tile view"
            } else if self.settings.debug_fresnel {
                ", Fresnel view"
            } else if self.settings.debug_cover {
                ", cover view"
            } else if self.settings.debug_far {
                ", far-field view"
            } else {
                ""
            },
            if self.settings.debug_bounds { ", cluster bounds" } else { "" },
            if self.settings.debug_wind { ", wind arrows" } else { "" },
            if self.settings.debug_pressed { ", pressed view" } else { "" },
            if self.settings.debug_patches { ", patches view" } else { "" },
            if self.settings.wireframe { ", wireframe" } else { "" },
            match self.settings.msaa {
                m if !m.enabled() => String::new(),
                m => format!(
                    ", {}x MSAA {}",
                    m.samples,
                    if m.alpha_to_coverage { "alpha to coverage" } else { "alpha test" }
                ),
            },
            self.options.scene.landscape_summary(),
        );
    }
}

/// What the cull and LOD do, for the rebuild report.
fn culling_state(culling: &crate::render::culling::Culling) -> String {
    if !culling.enabled {
        return "brute force".into();
    }
    let lod = match (culling.density, culling.segment_lod) {
        (true, true) => "density and segment LOD",
        (true, false) => "density LOD",
        (false, true) => "segment LOD",
        (false, false) => "no LOD",
    };
    let outline = if culling.solid_outline { ", outline as geometry" } else { "" };
    format!("GPU culling, {lod} {:?}{outline}", culling.buckets())
}
