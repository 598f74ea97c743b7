//! Specialization constants of the scene pipelines (`shaders/common/common.glsl`, `bindings.glsl`): how
//! the blades are animated is compiled into each pipeline, so a configuration pays only for its
//! own path (llvmpipe, like most GPUs, runs both sides of a uniform branch as masked code).

use crate::render::gpu_constants as gpu;

/// `RENDER_FLAGS` bits, generated from `shaders/common/shared.glsl`.
pub use crate::render::gpu_constants::{
    FLAG_CLUSTER_PUSH, FLAG_CULLED, FLAG_DEBUG_FORCE, FLAG_DEBUG_LOD, FLAG_EVAL_BLADE,
};

/// Number of specialization constants, one per `SPEC_*` id of `shaders/common/shared.glsl`.
pub const COUNT: usize = 15;

/// The constants; each field's `constant_id` is the `SPEC_*` named in its doc (`Self::pairs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Specialization {
    /// `SPEC_KEYFRAME_UVEC4S`: `uvec4`s of the keyframe uniform array.
    pub keyframe_uvec4s: u32,
    /// `SPEC_ANIMATION_MODE`: a `MODE_*` code.
    pub mode: u32,
    /// `SPEC_SMOOTHING`: 0 nearest, 1 linear, 2 slerp.
    pub smoothing: u32,
    /// `SPEC_KEYFRAME_ENCODING`: texture encoding (0..=2) or uniform packing (3, 4).
    pub encoding: u32,
    /// `SPEC_ATTENUATION`: an `ATTENUATION_*` code.
    pub attenuation: u32,
    /// `SPEC_REPRESENTATION`: a `REPRESENTATION_*` code.
    pub representation: u32,
    /// `SPEC_RENDER_FLAGS`: `FLAG_*` bits.
    pub flags: u32,
    /// `SPEC_SEGMENTS`: segments per blade.
    pub segments: u32,
    /// `SPEC_BLADES_PER_INSTANCE`: blades per instance (1: the strip alone, no degenerate joins, no tail test).
    pub blades_per_instance: u32,
    /// `SPEC_ENCODE_SRGB`: 1 when the shaders encode sRGB (UNORM targets), 0 when the format does.
    pub encode_srgb: u32,
    /// `SPEC_MODEL_SEGMENTS`: segments of the animation model's levels (`segments` may be fewer
    /// in a LOD bucket's pipeline).
    pub model_segments: u32,
    /// `SPEC_CULL_GROUP`: invocations of a cull workgroup (`passes::cull::workgroup_size`).
    pub cull_group: u32,
    /// `SPEC_MSAA_SAMPLES`: samples per pixel of the scene (`--msaa`).
    pub msaa_samples: u32,
    /// `SPEC_STRIP_AREA`: an `f32`'s bits, the solid outline's width scale for a strip of
    /// `segments` (`scene::alpha::strip_area_scale`; a LOD bucket's, `bucket_constants`).
    pub strip_area: u32,
    /// `SPEC_STRIP_L6`: an `f32`'s bits, the l^6 scale of a strip of `segments` over the model's
    /// (`scene::alpha::strip_l6_scale`).
    pub strip_l6: u32,
}

impl Specialization {
    /// The constants of the blade geometry, the target and the debug view, for static blades;
    /// the animation model then sets its own (`AnimationModel::specialize`).
    /// The blade geometry (segments, blades per instance) is compiled in too: the vertex shader's
    /// index arithmetic then divides by constants, which llvmpipe would otherwise do lane by lane.
    pub fn new(
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
        Self {
            keyframe_uvec4s: 1,
            mode: gpu::MODE_STATIC,
            smoothing: 0,
            encoding: 0,
            attenuation: gpu::ATTENUATION_CLUSTER,
            representation: gpu::REPRESENTATION_LEVELS,
            flags,
            segments,
            blades_per_instance,
            encode_srgb: u32::from(encode_srgb),
            model_segments: segments,
            cull_group: 64,
            msaa_samples: 1,
            strip_area: 1.0f32.to_bits(),
            strip_l6: 1.0f32.to_bits(),
        }
    }

    /// Every constant as `(constant_id, value)`, the ids generated from `shaders/common/shared.glsl`.
    pub fn pairs(&self) -> [(u32, u32); COUNT] {
        [
            (gpu::SPEC_KEYFRAME_UVEC4S, self.keyframe_uvec4s),
            (gpu::SPEC_ANIMATION_MODE, self.mode),
            (gpu::SPEC_SMOOTHING, self.smoothing),
            (gpu::SPEC_KEYFRAME_ENCODING, self.encoding),
            (gpu::SPEC_ATTENUATION, self.attenuation),
            (gpu::SPEC_REPRESENTATION, self.representation),
            (gpu::SPEC_RENDER_FLAGS, self.flags),
            (gpu::SPEC_SEGMENTS, self.segments),
            (gpu::SPEC_BLADES_PER_INSTANCE, self.blades_per_instance),
            (gpu::SPEC_ENCODE_SRGB, self.encode_srgb),
            (gpu::SPEC_MODEL_SEGMENTS, self.model_segments),
            (gpu::SPEC_CULL_GROUP, self.cull_group),
            (gpu::SPEC_MSAA_SAMPLES, self.msaa_samples),
            (gpu::SPEC_STRIP_AREA, self.strip_area),
            (gpu::SPEC_STRIP_L6, self.strip_l6),
        ]
    }

    /// The values indexed by `constant_id`, as `vk::pipeline` takes them (`constants[i]` is
    /// `constant_id = i`). The ids of `pairs` are `0..COUNT` in some order (asserted at compile
    /// time below), so every slot is written exactly once.
    pub fn constants(&self) -> [u32; COUNT] {
        let mut values = [0; COUNT];
        for (id, value) in self.pairs() {
            values[id as usize] = value;
        }
        values
    }
}

/// The `SPEC_*` ids, in `Specialization::pairs` order.
const IDS: [u32; COUNT] = [
    gpu::SPEC_KEYFRAME_UVEC4S,
    gpu::SPEC_ANIMATION_MODE,
    gpu::SPEC_SMOOTHING,
    gpu::SPEC_KEYFRAME_ENCODING,
    gpu::SPEC_ATTENUATION,
    gpu::SPEC_REPRESENTATION,
    gpu::SPEC_RENDER_FLAGS,
    gpu::SPEC_SEGMENTS,
    gpu::SPEC_BLADES_PER_INSTANCE,
    gpu::SPEC_ENCODE_SRGB,
    gpu::SPEC_MODEL_SEGMENTS,
    gpu::SPEC_CULL_GROUP,
    gpu::SPEC_MSAA_SAMPLES,
    gpu::SPEC_STRIP_AREA,
    gpu::SPEC_STRIP_L6,
];

/// Whether `ids` is a permutation of `0..COUNT`: dense, so `constants()` fills every slot.
const fn dense(ids: &[u32; COUNT]) -> bool {
    let mut seen = [false; COUNT];
    let mut i = 0;
    while i < COUNT {
        let id = ids[i] as usize;
        if id >= COUNT || seen[id] {
            return false;
        }
        seen[id] = true;
        i += 1;
    }
    true
}

const _: () = assert!(dense(&IDS), "the SPEC_* ids of shaders/common/shared.glsl must be 0..COUNT, each once");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_use_the_generated_ids_in_order() {
        let spec = Specialization {
            keyframe_uvec4s: 100,
            mode: 101,
            smoothing: 102,
            encoding: 103,
            attenuation: 104,
            representation: 105,
            flags: 106,
            segments: 107,
            blades_per_instance: 108,
            encode_srgb: 109,
            model_segments: 110,
            cull_group: 111,
            msaa_samples: 112,
            strip_area: 113,
            strip_l6: 114,
        };
        assert_eq!(spec.pairs().map(|(id, _)| id), IDS);
        let constants = spec.constants();
        for (id, value) in spec.pairs() {
            assert_eq!(constants[id as usize], value);
        }
        assert_eq!(constants[gpu::SPEC_SEGMENTS as usize], 107);
        assert_eq!(constants[gpu::SPEC_KEYFRAME_UVEC4S as usize], 100);
    }
}
