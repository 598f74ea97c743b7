//! The renderer's side of the blade response (`render::animation::response`): the models it is
//! built with, building a response with the pose records it writes, and swapping them on a
//! rebuild.

use std::rc::Rc;

use super::Renderer;
use crate::error::Result;
use crate::render::animation::poses::PoseRecords;
use crate::render::animation::response::{BladeResponse, BuildResponse, ResponseContext};
use crate::render::animation::{self, AnimationSettings};
use crate::render::scene_gpu::pose_records;
use crate::render::wind::{AnalyticWind, WindField};
use crate::render::RenderSettings;

/// The models a renderer animates its blades with: the wind field and what builds the blade
/// response (for each build: `rebuild` builds a new one when the animation changes).
pub struct Models {
    /// The wind field.
    pub wind: Box<dyn WindField>,
    /// Builds the blade response.
    pub response: Rc<BuildResponse>,
}

impl Default for Models {
    /// The CLI's: the analytic wind and the response `--mode` names (`animation::build_response`).
    fn default() -> Self {
        Self { wind: Box::new(AnalyticWind::new()), response: Rc::new(animation::build_response) }
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
        let response = (self.response_builder)(device, &context)?;
        // Destroyed if the records cannot be made: nothing has used it.
        let response = crate::vk::Guard::new(device, response);
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
