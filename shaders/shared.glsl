// The one source of truth for the integer constants the shaders and Rust share: descriptor
// bindings, specialization-constant ids, flag bits, mode codes and limits. build.rs parses this
// file and writes each `#define NAME VALUE // doc` as `pub const NAME: u32 = VALUE;` with the doc
// into `render::gpu_constants`; Rust uses those, never a copy. The parser is strict: besides
// `#define` lines it accepts only `//` comments, blank lines and the include guard, and a define
// needs a name in upper case, a decimal value (a `u` suffix is allowed) and a doc comment.
#ifndef MEADOW_SHARED_GLSL
#define MEADOW_SHARED_GLSL

// Descriptor sets of the scene pipelines.
#define SET_SCENE 0 // The scene and this frame's uniforms and forces (`render::scene_gpu::bindings`).
#define SET_ANIMATION 1 // The animation model's resources (`render::animation::model::bindings`).

// Set `SET_SCENE`.
#define BINDING_FRAME 0 // `FrameUniforms` uniform buffer.
#define BINDING_BLADES 1 // `BladeInstance[]` storage buffer.
#define BINDING_HEIGHTS 2 // Terrain heights storage buffer.
#define BINDING_BLADE_ALPHA 3 // Blade alpha texture.
#define BINDING_CLUSTERS 4 // `BladeCluster[]` storage buffer.
#define BINDING_CORNERS 5 // Per-frame corner forces.
#define BINDING_EMITTERS 6 // Per-frame point sources and colliders.

// Set `SET_ANIMATION`: every model fills all three (the blade shaders declare them all).
#define BINDING_KEYFRAMES 0 // Keyframe texture.
#define BINDING_KEYFRAME_WORDS 1 // Keyframe uniform array.
#define BINDING_POSES 2 // Per-blade pose records written by a model's compute pass (`--eval blade`).

// Specialization-constant ids (`layout(constant_id = SPEC_*)`), filled by
// `render::specialization::Specialization`.
#define SPEC_KEYFRAME_UVEC4S 0 // `uvec4`s of the keyframe uniform array.
#define SPEC_ANIMATION_MODE 1 // `MODE_*`: how the blades are animated.
#define SPEC_SMOOTHING 2 // 0 nearest, 1 linear (eq. 3.13), 2 slerp (eq. 3.14).
#define SPEC_KEYFRAME_ENCODING 3 // Texture encoding 0 rgba8x2, 1 unorm16, 2 float32; uniform packing 3 thesis-merged, 4 snorm16x2.
#define SPEC_ATTENUATION 4 // `ATTENUATION_*`: where the wind is attenuated.
#define SPEC_REPRESENTATION 5 // `REPRESENTATION_*`: how a pose is represented.
#define SPEC_RENDER_FLAGS 6 // `FLAG_*` bits.
#define SPEC_SEGMENTS 7 // Segments per blade, at most `MAX_SEGMENTS`.
#define SPEC_BLADES_PER_INSTANCE 8 // Blades per instance (1: the strip alone, no degenerate joins, no tail test).
#define SPEC_ENCODE_SRGB 9 // 1 when the shaders encode sRGB (UNORM targets), 0 when the target's format does.

// `SPEC_RENDER_FLAGS` bits.
#define FLAG_DEBUG_FORCE 1u // Colour blades by force magnitude (thesis fig. 4.5 / 6.1c).
#define FLAG_EVAL_BLADE 2u // Pose records come from the blade-pose compute pass, once per blade.
#define FLAG_CLUSTER_PUSH 4u // Per-cluster draws push their first blade (`meadow overhead`).

// `SPEC_ANIMATION_MODE` codes.
#define MODE_STATIC 0u // No animation.
#define MODE_TEXTURE 1u // Keyframes from the keyframe texture.
#define MODE_UNIFORM 2u // Keyframes from the keyframe uniform array (thesis 4.4.2).

// `SPEC_ATTENUATION` codes (thesis 4.5).
#define ATTENUATION_CLUSTER 0u // Point sources attenuated at the cluster corners.
#define ATTENUATION_BLADE 1u // Point sources and colliders evaluated at every blade.

// `SPEC_REPRESENTATION` codes.
#define REPRESENTATION_LEVELS 0u // Keyframe vertex levels.
#define REPRESENTATION_CURVE 1u // A Bézier curve fitted to the keyframe.

// Limits.
#define MAX_SEGMENTS 16u // Segments per blade; shader arrays of levels hold `MAX_SEGMENTS + 1`.
#define MAX_EMITTERS 64u // Point sources plus colliders a renderer can hold (the per-frame emitter buffers' capacity).
#define POSE_WORDS 3u // 32-bit words of one level of a `--eval blade` pose record.

#endif
