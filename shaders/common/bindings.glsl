// The descriptor sets of the scene pipelines: the scene and this frame's uniforms and forces
// (`SET_SCENE`, `render::layouts::scene_bindings`), then the animation model's resources
// (`SET_ANIMATION`). Numbers are in shared.glsl; the set layouts are reflected from the shaders.
#ifndef MEADOW_BINDINGS_GLSL
#define MEADOW_BINDINGS_GLSL
#include "common/common.glsl"

// Backend profiles (`vk::profile::Profile`; build.rs builds every shader once with
// MEADOW_PROFILE_LAVAPIPE and once with MEADOW_PROFILE_GENERIC defined). The generic profile binds
// each resource once, as the shader reads it. The lavapipe profile binds some twice (its "twins"),
// for Mesa 22.3's llvmpipe:
// - THE RULE: a value that decides control flow (an `if`, a loop bound) is read through a storage
//   binding, never a uniform one. Lavapipe before Mesa 23.1 "inlines" uniform-buffer values that
//   decide branches: when a compute pipeline's `if` or loop bound reads only uniforms, each
//   dispatch after a descriptor bind compiles a new variant with this frame's values folded in,
//   and keeps every one (`update_inline_shader_state` in lvp_execute.c has no variant cache before
//   23.1). The cull tests its toggles and counts that way, so the viewer's memory grew by about
//   1.1 MB a frame, all of it JIT code. Storage buffers are never inlined. The cull's passes
//   (FRAME_FROM_STORAGE) therefore read `frame` from a storage binding of the same buffer (same
//   std140 layout), and `frame_values`, for reads that only enter arithmetic, from the uniform
//   one: llvmpipe loads a uniform at a constant offset once for all lanes, where a storage load is
//   a loop over the SIMD lanes with a bounds test and a branch per lane (`emit_load_mem`).
// - Storage buffers that shaders gather from are read through texel views (`blade_record`,
//   `visible_entry`, `relief_vertex`, `level_word`, the cull's verdicts and depth pyramid): a
//   vector gather on llvmpipe instead of a load per SIMD lane and word (`vk::buffer::TexelView`).
#if defined(MEADOW_PROFILE_LAVAPIPE)
#define TEXEL_TWINS
#elif !defined(MEADOW_PROFILE_GENERIC)
#error "build.rs defines MEADOW_PROFILE_LAVAPIPE or MEADOW_PROFILE_GENERIC"
#endif

#if defined(FRAME_FROM_STORAGE) && defined(TEXEL_TWINS)
layout(set = SET_SCENE, binding = BINDING_FRAME_STORAGE, std140) readonly buffer FrameStorage { FrameUniforms frame; };
layout(set = SET_SCENE, binding = BINDING_FRAME, std140) uniform Frame { FrameUniforms frame_values; };
#else
layout(set = SET_SCENE, binding = BINDING_FRAME, std140) uniform Frame { FrameUniforms frame; };
// One binding: `frame_values` is `frame`.
#define frame_values frame
#endif
#ifdef TEXEL_TWINS
// The blades (`BladeInstance`) as two RGBA32UI texels each: the scene's shaders read a blade with
// `blade_record`.
layout(set = SET_SCENE, binding = BINDING_BLADE_TEXELS) uniform usamplerBuffer blade_texels;

BladeInstance blade_record(uint index) {
    uvec4 a = texelFetch(blade_texels, int(2u * index));
    uvec4 b = texelFetch(blade_texels, int(2u * index + 1u));
    BladeInstance blade;
    blade.position = uintBitsToFloat(a.xyz);
    blade.facing = uintBitsToFloat(a.w);
    blade.height = uintBitsToFloat(b.x);
    blade.width = uintBitsToFloat(b.y);
    blade.stiffness = uintBitsToFloat(b.z);
    blade.variation = b.w;
    return blade;
}
#else
layout(set = SET_SCENE, binding = BINDING_BLADES, std430) readonly buffer Blades { BladeInstance blades[]; };
BladeInstance blade_record(uint index) {
    return blades[index];
}
#endif
layout(set = SET_SCENE, binding = BINDING_HEIGHTS, std430) readonly buffer Heights { float heights[]; };
layout(set = SET_SCENE, binding = BINDING_BLADE_ALPHA) uniform sampler2D blade_alpha;
layout(set = SET_SCENE, binding = BINDING_CLUSTERS, std430) readonly buffer Clusters { BladeCluster clusters[]; };
// Per frame: forces at cluster corners (xy force, z calm-area exposure), and point sources
// (x, z, power, sigma) followed by colliders (centre x, z, radius x, z).
layout(set = SET_SCENE, binding = BINDING_CORNERS, std430) readonly buffer Corners { vec4 corners[]; };
layout(set = SET_SCENE, binding = BINDING_EMITTERS, std430) readonly buffer Emitters { vec4 emitters[]; };
layout(set = SET_SCENE, binding = BINDING_TILES, std430) readonly buffer Tiles { BladeTile tiles[]; };
// The cull's output (cull_emit.comp writes it): x the blade (`visible_blade` in cull.glsl), y
// its root height as a half float (a block field's; low 16 bits), fade and widening as unorm8
// (`visible_scale`, `visible_unpack`).
// Fade in [0, 1] and widening in [1, lod.w] as unorm8, both exact at 1 (no LOD: the same blade).
uint visible_scale(float root_y, vec2 scale) {
    vec2 unit = vec2(scale.x, (scale.y - 1.0) / max(frame_values.lod.w - 1.0, 1e-6));
    uvec2 bytes = uvec2(round(clamp(unit, 0.0, 1.0) * 255.0));
    return (packHalf2x16(vec2(root_y, 0.0)) & 0xffffu) | (bytes.x << 16) | (bytes.y << 24);
}

// (root height, fade, widening) of a visible entry's second word.
vec3 visible_unpack(uint word) {
    return vec3(unpackHalf2x16(word & 0xffffu).x, float((word >> 16) & 255u) / 255.0,
        1.0 + float(word >> 24) / 255.0 * (frame_values.lod.w - 1.0));
}

// A visible entry that draws nothing: the padding of a bucket's last instance (cull_scan.comp).
const uint VISIBLE_PADDING = 0xffffffffu;

#ifdef CULL_WRITER
layout(set = SET_SCENE, binding = BINDING_VISIBLE, std430) writeonly buffer Visible { uvec2 visible[]; };
#elif defined(TEXEL_TWINS)
// Its readers fetch it as RG32UI texels (`vk::buffer::TexelView`).
layout(set = SET_SCENE, binding = BINDING_VISIBLE_TEXELS) uniform usamplerBuffer visible_texels;
uvec2 visible_entry(uint i) {
    return texelFetch(visible_texels, int(i)).xy;
}
#else
layout(set = SET_SCENE, binding = BINDING_VISIBLE, std430) readonly buffer Visible { uvec2 visible[]; };
uvec2 visible_entry(uint i) {
    return visible[i];
}
#endif
// A block field's terrain grid (FIELD_TERRAIN_CELLS² cells around O, field.glsl's
// `terrain_grid_offset`), a camera grid (camera_grid.glsl): per vertex, in the slot of its world
// vertex, the relief's height, the coarse mesh's height there and the relief's normal (x, z),
// filled as vertices enter the window by relief_grid.comp; the terrain, the cull and the blades'
// lighting read it (field.glsl, `relief_vertex`) instead of summing the relief's waves per
// vertex, blade and level.
#ifdef RELIEF_GRID_WRITER
layout(set = SET_SCENE, binding = BINDING_RELIEF_GRID, std430) writeonly buffer ReliefGrid { vec4 relief_grid[]; };
#elif defined(TEXEL_TWINS)
layout(set = SET_SCENE, binding = BINDING_RELIEF_GRID_TEXELS) uniform samplerBuffer relief_texels;
vec4 relief_texel(int i) {
    return texelFetch(relief_texels, i);
}
#else
layout(set = SET_SCENE, binding = BINDING_RELIEF_GRID, std430) readonly buffer ReliefGrid { vec4 relief_grid[]; };
vec4 relief_texel(int i) {
    return relief_grid[i];
}
#endif
layout(set = SET_ANIMATION, binding = BINDING_KEYFRAMES) uniform sampler2D keyframe_texture;
// Keyframes as a uniform array (thesis 4.4.2): two keyframe words per uvec4 half; the array fills
// min(maxUniformBufferRange, 64 KiB), set by the pipeline (`render::animation::keyframe_gpu::KeyframeUniforms::capacity`).
// A buffer block, so sizing it by a specialization constant is fine; arrays in shader code are
// sized by the fixed limits of shared.glsl.
layout(constant_id = SPEC_KEYFRAME_UVEC4S) const uint KEYFRAME_UVEC4S = 4096u;
layout(set = SET_ANIMATION, binding = BINDING_KEYFRAME_WORDS, std140) uniform KeyframeWords { uvec4 keyframe_words[KEYFRAME_UVEC4S]; };
// `--eval blade`: the evaluated blade, written by blade_pose.comp and read by blade.vert:
// POSE_WORDS words per level, MODEL_SEGMENTS + 1 levels per blade: the local-frame point divided by
// the blade's height and by POSE_SCALE (snorm16 x y | z, and the twist's cos and sin as snorm8),
// then the unit tangent and the force magnitude for the debug view (snorm8 x4).
#ifdef POSE_WRITER
layout(set = SET_ANIMATION, binding = BINDING_POSES, std430) writeonly buffer Poses { uint poses[]; };
#else
layout(set = SET_ANIMATION, binding = BINDING_POSES, std430) readonly buffer Poses { uint poses[]; };
#endif
// With the cull and pose records: each drawn blade's strip levels, placed and lit once per blade by
// blade_levels.comp, so blade.vert only widens and projects them. Entry i of the visible list owns
// MODEL_SEGMENTS + 1 levels from level i * (MODEL_SEGMENTS + 1); its bucket's SEGMENTS + 1 are
// written. A level is LEVEL_UVEC2S uvec2: the centre line's point (f32 x3, relative to the origin
// like every position), the full width across as a horizontal vector (half floats x, z), the lit
// and fogged colour and the fog transmittance (half floats), as blade.vert computed per vertex.
#ifdef LEVELS_WRITER
layout(set = SET_ANIMATION, binding = BINDING_LEVELS, std430) writeonly buffer Levels { uvec2 levels[]; };
#elif defined(TEXEL_TWINS)
// blade.vert fetches them as RG32UI texels (`vk::buffer::TexelView`): llvmpipe runs vertex
// shaders on one thread, where a storage load per SIMD lane and word costs most.
layout(set = SET_ANIMATION, binding = BINDING_LEVEL_TEXELS) uniform usamplerBuffer level_texels;
uvec2 level_word(uint i) {
    return texelFetch(level_texels, int(i)).xy;
}
#else
layout(set = SET_ANIMATION, binding = BINDING_LEVELS, std430) readonly buffer Levels { uvec2 levels[]; };
uvec2 level_word(uint i) {
    return levels[i];
}
#endif
const float POSE_SCALE = 2.0; // local point / height lies within ±POSE_SCALE

#endif
