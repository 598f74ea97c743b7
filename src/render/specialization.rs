//! Specialization constants of the scene pipelines (`shaders/common.glsl`, `bindings.glsl`): how
//! the blades are animated is compiled into each pipeline, so a configuration pays only for its
//! own path (llvmpipe, like most GPUs, runs both sides of a uniform branch as masked code).

use crate::keyframes::Representation;
use crate::render::animation::{AnimationSettings, Eval, KeyframeUniforms, Mode};
use crate::vk::Device;
use crate::wind::Attenuation;

/// `RENDER_FLAGS` bit: colour blades by force magnitude.
pub const FLAG_DEBUG_FORCE: u32 = 1;
/// `RENDER_FLAGS` bit: pose records come from the blade-pose compute pass.
pub const FLAG_EVAL_BLADE: u32 = 2;
/// `RENDER_FLAGS` bit: per-cluster draws push their first blade.
pub const FLAG_CLUSTER_PUSH: u32 = 4;

/// The constants, by `constant_id`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Specialization {
    /// 0: `uvec4`s of the keyframe uniform array.
    pub keyframe_uvec4s: u32,
    /// 1: 0 static, 1 texture, 2 uniform.
    pub mode: u32,
    /// 2: 0 nearest, 1 linear, 2 slerp.
    pub smoothing: u32,
    /// 3: texture encoding (0..=2) or uniform packing (3, 4).
    pub encoding: u32,
    /// 4: 0 cluster, 1 blade.
    pub attenuation: u32,
    /// 5: 0 vertex levels, 1 curve.
    pub representation: u32,
    /// 6: `FLAG_*` bits.
    pub flags: u32,
    /// 7: segments per blade.
    pub segments: u32,
    /// 8: blades per instance (1: the strip alone, no degenerate joins, no tail test).
    pub blades_per_instance: u32,
    /// 9: 1 when the shaders encode sRGB (UNORM targets), 0 when the format does.
    pub encode_srgb: u32,
}

impl Specialization {
    /// The constants for an animation on `device`.
    /// The blade geometry (segments, blades per instance) is compiled in too: the vertex shader's
    /// index arithmetic then divides by constants, which llvmpipe would otherwise do lane by lane.
    pub fn new(
        device: &Device,
        animation: &AnimationSettings,
        debug_force: bool,
        segments: u32,
        blades_per_instance: u32,
        cluster_push: bool,
        encode_srgb: bool,
    ) -> Self {
        let mut flags = 0;
        if debug_force {
            flags |= FLAG_DEBUG_FORCE;
        }
        if cluster_push {
            flags |= FLAG_CLUSTER_PUSH;
        }
        if animation.eval == Eval::Blade && animation.mode != Mode::Static {
            flags |= FLAG_EVAL_BLADE;
        }
        Self {
            keyframe_uvec4s: KeyframeUniforms::capacity(device),
            mode: animation.mode.code(),
            smoothing: animation.smoothing.code(),
            encoding: match animation.mode {
                Mode::Uniform => animation.packing.code(),
                _ => animation.encoding.code(),
            },
            attenuation: match animation.attenuation {
                Attenuation::Cluster => 0,
                Attenuation::Blade => 1,
            },
            representation: u32::from(animation.representation == Representation::Curve),
            flags,
            segments,
            blades_per_instance,
            encode_srgb: u32::from(encode_srgb),
        }
    }

    /// Whether the blade-pose compute pass runs.
    pub fn eval_blade(&self) -> bool {
        self.flags & FLAG_EVAL_BLADE != 0
    }

    /// The values in `constant_id` order.
    pub fn constants(&self) -> [u32; 10] {
        [
            self.keyframe_uvec4s,
            self.mode,
            self.smoothing,
            self.encoding,
            self.attenuation,
            self.representation,
            self.flags,
            self.segments,
            self.blades_per_instance,
            self.encode_srgb,
        ]
    }
}
