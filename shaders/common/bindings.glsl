// The descriptor sets of the scene pipelines: the scene and this frame's uniforms and forces
// (`SET_SCENE`), then the pose records a blade response writes and the blade pass reads
// (`SET_POSES`); the set layouts are reflected from the shaders. Set 0's resources are declared by
// their owners' headers, numbered by build.rs (`layout(SCENE(Name), …)`, common/profile.glsl);
// this header includes the ones the scene passes share. A new set-0 resource needs no line here:
// its readers include its header. Set 1's numbers are in shared.glsl. A response's own resources
// (the keyframe tables) are declared by its own headers in its passes' own sets.
#ifndef MEADOW_BINDINGS_GLSL
#define MEADOW_BINDINGS_GLSL
#include "common/profile.glsl"
#include "common/frame.glsl"
#include "blades/blade_records.glsl"
#include "blades/blade_alpha.glsl"
#include "blades/clusters.glsl"
#include "animation/frame_forces.glsl"
#include "cull/tiles.glsl"
#include "cull/visible.glsl"
#include "terrain/ground_texels.glsl"

// `--eval blade`: the evaluated blade, written by blade_pose.comp and read by blade.vert:
// POSE_WORDS words per level, MODEL_SEGMENTS + 1 levels per blade: the local-frame point divided by
// the blade's height and by POSE_SCALE (snorm16 x y | z, and the twist's cos and sin as snorm8),
// then the unit tangent and the force magnitude for the debug view (snorm8 x4).
#ifdef POSE_WRITER
layout(set = SET_POSES, binding = BINDING_POSES, std430) writeonly buffer Poses { uint poses[]; };
#elif defined(POSE_EDITOR)
// A pass that moves what a response wrote (animation/push_out.comp) reads and writes them.
layout(set = SET_POSES, binding = BINDING_POSES, std430) buffer Poses { uint poses[]; };
#else
layout(set = SET_POSES, binding = BINDING_POSES, std430) readonly buffer Poses { uint poses[]; };
#endif
// With the cull and pose records: each drawn blade's strip levels, placed and lit once per blade by
// blade_levels.comp, so blade.vert only widens and projects them. Entry i of the visible list owns
// MODEL_SEGMENTS + 1 levels from level i * (MODEL_SEGMENTS + 1); its bucket's SEGMENTS + 1 are
// written. A level is LEVEL_UVEC2S uvec2: the centre line's point (f32 x3, relative to the origin
// like every position), the full width across as a horizontal vector (half floats x, z), the lit
// and fogged colour and the fog transmittance (half floats), as blade.vert computed per vertex.
#ifdef LEVELS_WRITER
layout(set = SET_POSES, binding = BINDING_LEVELS, std430) writeonly buffer Levels { uvec2 levels[]; };
#elif defined(TEXEL_TWINS)
// blade.vert fetches them as RG32UI texels (`vk::buffer::TexelView`): llvmpipe runs vertex
// shaders on one thread, where a storage load per SIMD lane and word costs most.
layout(set = SET_POSES, binding = BINDING_LEVEL_TEXELS) uniform usamplerBuffer level_texels;
uvec2 level_word(uint i) {
    return texelFetch(level_texels, int(i)).xy;
}
#else
layout(set = SET_POSES, binding = BINDING_LEVELS, std430) readonly buffer Levels { uvec2 levels[]; };
uvec2 level_word(uint i) {
    return levels[i];
}
#endif
const float POSE_SCALE = 2.0; // render::animation::poses::POSE_SCALE

#endif
