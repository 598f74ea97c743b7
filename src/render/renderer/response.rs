//! The renderer's side of the blade response (`render::animation::response`): the models it is
//! built with, building a response with the pose records it writes, and swapping them on a
//! rebuild.

use std::rc::Rc;

use super::Renderer;
use crate::error::{Error, Result};
use crate::render::animation::poses::PoseRecords;
use crate::render::animation::response::{BladeInput, BladeResponse, BuildResponse, ResponseContext};
use crate::render::animation::{self, AnimationSettings};
use crate::render::draw_class::{ClassLayout, DrawClasses};
use crate::render::scene_gpu::pose_records;
use crate::render::wind::{AnalyticWind, WindField};
use crate::render::RenderSettings;

/// The models a renderer animates and draws with: the wind field, what builds the blade response
/// (for each build: `rebuild` builds a new one when the animation changes) and the draw classes
/// the cull sorts into besides the blades (`render::draw_class`).
pub struct Models {
    /// The wind field.
    pub wind: Box<dyn WindField>,
    /// Builds the blade response.
    pub response: Rc<BuildResponse>,
    /// Further draw classes.
    pub classes: DrawClasses,
}

impl Default for Models {
    /// The CLI's: the analytic wind, the response `--mode` names (`animation::build_response`),
    /// the blade class alone.
    fn default() -> Self {
        let response = Rc::new(animation::build_response);
        Self { wind: Box::new(AnalyticWind::new()), response, classes: DrawClasses::default() }
    }
}

/// What the renderer builds again on each rebuild from its models: the blade response, and the
/// draw classes' passes and bucket layout (`ClassLayout`, placed again each frame for the
/// frame's LOD buckets).
pub(super) struct Builders {
    pub(super) response: Rc<BuildResponse>,
    pub(super) classes: DrawClasses,
}

/// Where every draw class's buckets lie for `settings`: the blade class's LOD buckets, then the
/// further `classes`' (`render::draw_class`).
pub(super) fn class_layout(settings: &RenderSettings, classes: &DrawClasses) -> Result<ClassLayout> {
    let culling = &settings.culling;
    ClassLayout::new(culling.buckets().len() as u32, culling.rows, classes, settings.blades_per_instance)
}

/// `classes`, with the flowers' (`render::flowers`) when `scene` has flowers; refused beside
/// classes of the caller's (one count shader holds one selection).
pub(super) fn with_flowers(scene: &crate::scene::Scene, classes: DrawClasses) -> Result<DrawClasses> {
    let none = classes.classes.is_empty() && classes.count_shader.is_none() && classes.source.is_none();
    match (scene.flowers.is_some(), none) {
        (false, _) => Ok(classes),
        (true, true) => Ok(crate::render::flowers::FlowerClass::classes()),
        (true, false) => Err(Error::Internal("flowers beside further draw classes: one count shader selects".into())),
    }
}

/// Flowers (a share of `flower_share`) need the cull, which claims them, and stems posed by the
/// response's pose records or drawn neutral: refused (bad input) with brute force, the floor or
/// a per-vertex response (`--eval vertex`), whose poses the flowers' pass cannot read.
fn check_flowers(flower_share: f32, settings: &RenderSettings, input: &BladeInput) -> Result<()> {
    if flower_share <= 0.0 {
        return Ok(());
    }
    let why = if !settings.culling.enabled {
        "the cull claims them: not with --brute-force"
    } else if settings.floor {
        "not with --mode floor"
    } else if matches!(input, BladeInput::PerVertex { .. }) {
        "their stems are posed by the blades' pose records: not with --eval vertex"
    } else {
        return Ok(());
    };
    Err(Error::BadInput(format!("--flowers: {why}")))
}

impl Renderer {
    /// `class_layout` for the renderer's settings and classes.
    pub(super) fn class_layout(&self) -> Result<ClassLayout> {
        class_layout(&self.settings, &self.builders.classes)
    }
}

/// A replaced response and its pose records, retired behind the frames that used them.
pub(super) type RetiredResponse = (Option<Box<dyn BladeResponse>>, Option<PoseRecords>);

impl Renderer {
    /// A blade response for `settings` and `animation`, and the pose records it writes (room for
    /// as many as the blade pass may draw when it poses blades once per blade, `PoseRecords::new`;
    /// a stand-in otherwise). On failure nothing is left.
    pub(super) fn build_response(
        &self,
        settings: &RenderSettings,
        animation: &AnimationSettings,
    ) -> Result<(Box<dyn BladeResponse>, PoseRecords)> {
        let (device, scene) = (&*self.device, self.scene_gpu());
        let culled = settings.culling.enabled;
        let context = ResponseContext { animation, segments: settings.segments, culled, scene };
        let response = (self.builders.response)(device, &context)?;
        // Destroyed if the records cannot be made: nothing has used it.
        let response = crate::vk::Guard::new(device, response);
        check_flowers(scene.flower_share, settings, &response.blade_input())?;
        for (on, view, what) in [
            (settings.debug_pressed, "pressed", "the pressed map bends"),
            (settings.debug_patches, "patches", "the interaction patches draw"),
        ] {
            if on && !response.blade_input().pose_records() {
                let why =
                    format!("it colours the pose records {what}, and these blades are posed per vertex or neutral");
                return Err(Error::BadInput(format!("--debug-view {view}: {why}")));
            }
        }
        let room = match response.blade_input().pose_records() {
            true => {
                let records = pose_records(device, scene, settings.segments).max(1);
                (records, crate::render::scene_gpu::level_room(scene, records, culled))
            }
            false => (0, 0),
        };
        let poses = PoseRecords::new(device, &self.layouts.poses, room, settings.segments)?;
        Ok((response.take(), poses))
    }

    /// Put `new` (a response and its pose records) in place of the current ones; returns those.
    pub(super) fn swap_response(
        &mut self,
        new: Option<(Box<dyn BladeResponse>, PoseRecords)>,
    ) -> (Option<Box<dyn BladeResponse>>, Option<PoseRecords>) {
        let (response, poses) = new.map_or((None, None), |(r, p)| (Some(r), Some(p)));
        (std::mem::replace(&mut self.response, response), std::mem::replace(&mut self.poses, poses))
    }
}
