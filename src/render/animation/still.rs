//! The static model: neutral Bézier blades, no forces on them (thesis 4.1). It needs no table
//! and no pass: stand-ins fill its descriptor set, and the forces are still computed each frame
//! (the debug views show them).

use crate::error::Result;
use crate::render::animation::model::{AnimationModel, AnimationSet, BladeInput, PassSetup};
use crate::render::animation::{KeyframeTexture, KeyframeUniforms};
use crate::render::gpu_constants as gpu;
use crate::render::graph::Pass;
use crate::render::specialization::Specialization;
use crate::render::uniforms::FrameUniforms;
use crate::vk::descriptor::SetLayout;
use crate::vk::upload::UploadBatch;
use crate::vk::{Device, Guard};

/// Static blades.
pub struct StaticModel {
    set: AnimationSet,
}

impl StaticModel {
    /// Upload the stand-ins and fill the set.
    pub fn new(device: &Device, set_layout: &SetLayout) -> Result<Self> {
        let mut batch = UploadBatch::new(device);
        let keyframes = KeyframeTexture::stand_in(&mut batch)?;
        let keyframes = Guard::new(device, keyframes);
        let words = KeyframeUniforms::stand_in(&mut batch)?;
        Ok(Self { set: AnimationSet::upload(device, set_layout, batch, keyframes.take(), words, ((0, 0), 0))? })
    }
}

impl AnimationModel for StaticModel {
    fn name(&self) -> &'static str {
        "static"
    }

    fn specialize(&self, specialization: &mut Specialization) {
        specialization.mode = gpu::MODE_STATIC;
        specialization.keyframe_uvec4s = self.set.words.uvec4s;
    }

    fn fill_uniforms(&self, _: &mut FrameUniforms) {}

    fn resources(&self) -> &AnimationSet {
        &self.set
    }

    fn blade_input(&self) -> BladeInput {
        BladeInput::PerVertex
    }

    fn passes(&self, _: &Device, _: &PassSetup) -> Result<Vec<Box<dyn Pass>>> {
        Ok(Vec::new())
    }

    unsafe fn destroy(self: Box<Self>, device: &Device) {
        // SAFETY: per the contract.
        unsafe { self.set.destroy(device) };
    }
}
