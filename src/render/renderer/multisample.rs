//! The renderer's linear intermediate (`render::msaa`): the multisampled images with `--msaa`,
//! single-sampled ones with `--fade blend`, what the scene passes draw into, made to fit each
//! frame's target.

use super::Renderer;
use crate::error::Result;
use crate::render::msaa::MultisampleTarget;
use crate::render::target::TargetView;
use crate::vk::{Access, Resource};

impl Renderer {
    /// What the scene passes draw into for a frame into `target`: the target itself, or with
    /// `--msaa` or `--fade blend` the linear pair, (re)made to fit it. A replaced pair is destroyed once the
    /// frames that used it have finished, and the graph forgets it.
    pub(super) fn scene_view(&mut self, target: &TargetView) -> Result<TargetView> {
        let (msaa, linear) = (self.settings.msaa, self.linear_scene());
        let fits = |m: &MultisampleTarget| linear && m.fits(target.extent, msaa.flag());
        if !self.multisampled.as_ref().is_none_or(fits) {
            let old = self.multisampled.take().expect("checked");
            let view = old.view();
            self.graph.forget(Resource::color(view.color));
            self.graph.forget(Resource::depth(view.depth));
            self.ring.forget_replays();
            // SAFETY: the frames that used it have finished (the deletion queue's rule).
            self.ring.defer(&self.device, Box::new(move |device| unsafe { old.destroy(device) }));
        }
        if !linear {
            return Ok(*target);
        }
        if self.multisampled.is_none() {
            if !msaa.enabled() {
                // `--fade blend`'s single-sampled pair, which the checks before the renderer do
                // not count (they count the multisampled one): checked before it is made.
                let bytes = crate::render::msaa::linear_bytes(target.extent);
                let what = format!("--fade blend's linear scene at {}x{}", target.extent.width, target.extent.height);
                self.device.check_budget(bytes, &what)?;
            }
            self.multisampled = Some(MultisampleTarget::new(&self.device, target.extent, msaa.flag())?);
        }
        let view = self.multisampled.as_ref().expect("made").view();
        // Imported when made, and again if the graph lost track of it: a frame that failed to
        // record or submit (or `record_only`) puts the states back as they were before it,
        // when the images, never used by the GPU, had not been imported yet.
        for resource in [Resource::color(view.color), Resource::depth(view.depth)] {
            if !self.graph.states().get(resource).is_some_and(|s| s.is_imported()) {
                self.graph.import(resource, &[Access::Nothing]);
            }
        }
        Ok(view)
    }

    /// Whether the scene passes draw into the linear intermediate (`RenderSettings::linear_scene`):
    /// with `--msaa`, or blending a far field, which only a block field has.
    pub(super) fn linear_scene(&self) -> bool {
        let field = self.scene.as_ref().is_some_and(|scene| scene.field.is_some());
        self.settings.msaa.enabled() || (field && self.settings.linear_scene())
    }

    /// Whether frames draw into the target's depth image (not with `--msaa` or `--fade blend`:
    /// the scene's depth is the intermediate's). A target that tracks its depth's last access
    /// needs to know.
    pub fn uses_target_depth(&self) -> bool {
        !self.linear_scene()
    }
}
