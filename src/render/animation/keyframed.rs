//! The thesis' model: every blade takes one of a table of precomputed poses (keyframes, ch. 3),
//! selected by the force on it (eq. 3.10–3.12) and blended with its neighbours (eq. 3.13/3.14).
//! The table lives in a texture (4.4.1) or a uniform array (4.4.2); the selection runs per vertex
//! in the blade shader (as the thesis did), or once per blade in the blade-pose compute pass that
//! writes pose records (`--eval blade`, the thesis' ch. 7 future work).

use crate::error::Result;
use crate::keyframes::{KeyframeLayout, Representation};
use crate::render::animation::model::{AnimationModel, AnimationSet, BladeInput, PassSetup};
use crate::render::animation::pose_pass::BladePosePass;
use crate::render::animation::{AnimationSettings, Eval, KeyframeTexture, KeyframeUniforms, Mode};
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::SetLayout;
use crate::vk::upload::UploadBatch;
use crate::vk::{Device, Guard};
use crate::wind::Attenuation;

/// Keyframed blades.
pub struct KeyframeModel {
    settings: AnimationSettings,
    segments: u32,
    layout: KeyframeLayout,
    set: AnimationSet,
}

impl KeyframeModel {
    /// Generate the table for `segments`, upload it both ways, and make room for `room` pose
    /// records and placed levels when blades are evaluated per blade.
    pub fn new(
        device: &Device,
        set_layout: &SetLayout,
        settings: &AnimationSettings,
        segments: u32,
        room: (u32, u32),
    ) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let (keyframes, table) = KeyframeTexture::new(&mut batch, segments, settings)?;
        let layout = keyframes.layout;
        let keyframes = Guard::new(device, keyframes);
        let words = KeyframeUniforms::new(&mut batch, &table, settings.packing)?;
        let room = match settings.eval {
            Eval::Blade => (room.0.max(1), room.1),
            Eval::Vertex => (0, 0),
        };
        let set = AnimationSet::upload(device, set_layout, batch, keyframes.take(), words, (room, segments))?;
        Ok(Self { settings: settings.clone(), segments, layout, set })
    }

    fn per_blade(&self) -> bool {
        self.settings.eval == Eval::Blade
    }
}

impl AnimationModel for KeyframeModel {
    fn name(&self) -> &'static str {
        match (self.settings.mode, self.per_blade()) {
            (Mode::Uniform, false) => "uniform keyframes",
            (Mode::Uniform, true) => "uniform keyframes per blade",
            (_, false) => "texture keyframes",
            (_, true) => "texture keyframes per blade",
        }
    }

    fn specialize(&self, specialization: &mut Specialization) {
        let s = &self.settings;
        specialization.keyframe_uvec4s = self.set.words.uvec4s;
        specialization.mode = s.mode.code();
        specialization.smoothing = s.smoothing.code();
        specialization.encoding = match s.mode {
            Mode::Uniform => s.packing.code(),
            _ => s.encoding.code(),
        };
        specialization.attenuation = match s.attenuation {
            Attenuation::Cluster => gpu::ATTENUATION_CLUSTER,
            Attenuation::Blade => gpu::ATTENUATION_BLADE,
        };
        specialization.representation = match s.representation {
            Representation::Curve => gpu::REPRESENTATION_CURVE,
            Representation::Vertex => gpu::REPRESENTATION_LEVELS,
        };
        if self.per_blade() {
            specialization.flags |= gpu::FLAG_EVAL_BLADE;
        }
    }

    fn fill_uniforms(&self, uniforms: &mut FrameUniforms) {
        uniforms.keyframes.x = self.layout.magnitudes;
        uniforms.keyframes.y = self.layout.angles;
        uniforms.keyframe_shape.x = match self.settings.representation {
            Representation::Vertex => self.segments,
            Representation::Curve => 3,
        };
    }

    fn resources(&self) -> &AnimationSet {
        &self.set
    }

    fn blade_input(&self) -> BladeInput {
        match self.per_blade() {
            true => BladeInput::PoseRecords(self.set.per_blade.poses.raw, self.set.per_blade.levels.raw),
            false => BladeInput::PerVertex,
        }
    }

    fn passes(&self, device: &Device, setup: &PassSetup) -> Result<Vec<Box<dyn Pass>>> {
        if !self.per_blade() {
            return Ok(Vec::new());
        }
        Ok(vec![Box::new(BladePosePass::new(device, setup, &self.set)?)])
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.set.destroy(device) };
    }
}
