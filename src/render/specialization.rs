//! Specialization constants of the scene pipelines (`shaders/common/common.glsl`, `bindings.glsl`): how
//! the blades are animated is compiled into each pipeline, so a configuration pays only for its
//! own path (llvmpipe, like most GPUs, runs both sides of a uniform branch as masked code).

use crate::render::gpu_constants as gpu;

/// `RENDER_FLAGS` bits, generated from `shaders/common/shared.glsl`.
pub use crate::render::gpu_constants::{
    FLAG_CLUSTER_PUSH, FLAG_CULLED, FLAG_DEBUG_FORCE, FLAG_DEBUG_LOD, FLAG_EVAL_BLADE,
};

/// Number of specialization constants the scene shaders declare.
pub const COUNT: usize = 22;

/// The constants; each field is the shaders' constant named in its doc (`Self::named`), whose id
/// build.rs assigns (`SPEC(NAME)`): no id is kept in Rust.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Specialization {
    /// `KEYFRAME_UVEC4S`: `uvec4`s of the keyframe uniform array.
    pub keyframe_uvec4s: u32,
    /// `ANIMATION_MODE`: a `MODE_*` code.
    pub mode: u32,
    /// `SMOOTHING`: 0 nearest, 1 linear, 2 slerp.
    pub smoothing: u32,
    /// `KEYFRAME_ENCODING`: texture encoding (0..=2) or uniform packing (3, 4).
    pub encoding: u32,
    /// `ATTENUATION`: an `ATTENUATION_*` code.
    pub attenuation: u32,
    /// `REPRESENTATION`: a `REPRESENTATION_*` code.
    pub representation: u32,
    /// `RENDER_FLAGS`: `FLAG_*` bits.
    pub flags: u32,
    /// `SEGMENTS`: segments per blade.
    pub segments: u32,
    /// `BLADES_PER_INSTANCE`: blades per instance (1: the strip alone, no degenerate joins, no tail test).
    pub blades_per_instance: u32,
    /// `ENCODE_SRGB`: 1 when the shaders encode sRGB (UNORM targets), 0 when the format does.
    pub encode_srgb: u32,
    /// `MODEL_SEGMENTS`: segments of the animation model's levels (`segments` may be fewer
    /// in a LOD bucket's pipeline).
    pub model_segments: u32,
    /// `CULL_GROUP`: invocations of a cull workgroup (`passes::cull::workgroup_size`).
    pub cull_group: u32,
    /// `MSAA_SAMPLES`: samples per pixel of the scene (`--msaa`).
    pub msaa_samples: u32,
    /// `STRIP_AREA`: an `f32`'s bits, the solid outline's width scale for a strip of
    /// `segments` (`scene::alpha::strip_area_scale`; a LOD bucket's, `bucket_constants`).
    pub strip_area: u32,
    /// `STRIP_L6`: an `f32`'s bits, the l^6 scale of a strip of `segments` over the model's
    /// (`scene::alpha::strip_l6_scale`).
    pub strip_l6: u32,
    /// `TILE_ROWS_CAPACITY`: 0 when the blade class draws each LOD bucket once, else its rows
    /// per bucket, one per visible tile (`render::draw_rows::TileRows`).
    pub tile_rows_capacity: u32,
    /// `LOD_BUCKET`: the LOD bucket a blade pipeline draws (its per-tile rows' records).
    pub lod_bucket: u32,
    /// `GROUND_CELLS`: cells per side of a level of the ground's clipmap (`render::ground`).
    pub ground_cells: u32,
    /// `GROUND_LEVELS`: the clipmap's levels for the view distance.
    pub ground_levels: u32,
    /// `GROUND_COVER`: 1 when the ground's cover thins the grass and tints the terrain
    /// (`scene::cover::Cover::active`).
    pub ground_cover: u32,
    /// `CLUMP_SIZE_MM`: a block field's clump size in millimetres (`scene::clumps`; 0: none).
    pub clump_size_mm: u32,
    /// `FLOWER_SHARE`: an `f32`'s bits, the share of candidate blades the flowers claim
    /// (`scene::flowers`; 0: none).
    pub flower_share: u32,
}

impl Specialization {
    /// The constants of the blade geometry, the target and the debug view, for static blades;
    /// the blade response then sets its own (`BladeResponse::specialize`).
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
            tile_rows_capacity: 0,
            lod_bucket: 0,
            ground_cells: gpu::FIELD_TERRAIN_CELLS,
            ground_levels: 1,
            ground_cover: 0,
            clump_size_mm: 0,
            flower_share: 0,
        }
    }

    /// Every constant by the name the shaders declare it with (`layout(constant_id =
    /// SPEC(NAME)) const … NAME`, `shaders/common/common.glsl` and `bindings.glsl`), as
    /// `vk::pipeline` takes them: it fills each constant a shader declares by its name (the id is
    /// build.rs's, reflected from the SPIR-V), and a declared constant missing here fails the
    /// pipeline's build.
    pub fn named(&self) -> [(&'static str, u32); COUNT] {
        [
            ("KEYFRAME_UVEC4S", self.keyframe_uvec4s),
            ("ANIMATION_MODE", self.mode),
            ("SMOOTHING", self.smoothing),
            ("KEYFRAME_ENCODING", self.encoding),
            ("ATTENUATION", self.attenuation),
            ("REPRESENTATION", self.representation),
            ("RENDER_FLAGS", self.flags),
            ("SEGMENTS", self.segments),
            ("BLADES_PER_INSTANCE", self.blades_per_instance),
            ("ENCODE_SRGB", self.encode_srgb),
            ("MODEL_SEGMENTS", self.model_segments),
            ("CULL_GROUP", self.cull_group),
            ("MSAA_SAMPLES", self.msaa_samples),
            ("STRIP_AREA", self.strip_area),
            ("STRIP_L6", self.strip_l6),
            ("TILE_ROWS_CAPACITY", self.tile_rows_capacity),
            ("LOD_BUCKET", self.lod_bucket),
            ("GROUND_CELLS", self.ground_cells),
            ("GROUND_LEVELS", self.ground_levels),
            ("GROUND_COVER", self.ground_cover),
            ("CLUMP_SIZE_MM", self.clump_size_mm),
            ("FLOWER_SHARE", self.flower_share),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders;
    use crate::vk::pipeline::specialization;
    use crate::vk::profile::Profile;

    #[test]
    fn every_constant_a_scene_shader_declares_is_given_by_name() {
        let spec = Specialization::new(false, 4, 1, false, true);
        let named = spec.named();
        for shader in shaders::SCENE {
            let code = shader.code(Profile::Lavapipe);
            let declared = crate::vk::reflect::spec_constants(shader.path, code).unwrap();
            assert!(declared.iter().any(|(_, n)| n == "SEGMENTS"), "{}: {declared:?}", shader.path);
            let (entries, data) = specialization(shader.path, code, &named).unwrap();
            assert_eq!(entries.len(), declared.len(), "{}", shader.path);
            // Each entry is the declared id with the value of its name.
            for ((id, name), (entry, value)) in declared.iter().zip(entries.iter().zip(&data)) {
                assert_eq!(entry.constant_id, *id);
                assert_eq!(Some(value), named.iter().find(|(n, _)| n == name).map(|(_, v)| v), "{name}");
            }
        }
    }

    #[test]
    fn a_declared_constant_nobody_gives_fails_naming_it() {
        let named = Specialization::new(false, 4, 1, false, true).named();
        let without: Vec<(&str, u32)> = named.iter().copied().filter(|(n, _)| *n != "MSAA_SAMPLES").collect();
        let code = shaders::BLADE_VERT.code(Profile::Generic);
        let error = specialization("blade.vert", code, &without).unwrap_err().to_string();
        assert!(error.contains("blade.vert") && error.contains("`MSAA_SAMPLES`"), "{error}");
        // A value no constant of the stage declares is left out, not an error: one list serves
        // every stage (hiz.comp declares none).
        let (entries, _) = specialization("hiz.comp", shaders::HIZ_COMP.code(Profile::Generic), &named).unwrap();
        assert!(entries.is_empty());
        // No list at all: the shader's defaults.
        assert!(specialization("blade.vert", code, &[]).unwrap().0.is_empty());
    }
}
