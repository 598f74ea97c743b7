// The backend profile a shader is built for, its one rule, and the scene set's binding numbers
// (`generated/scene_set.glsl`, written by build.rs: `layout(SCENE(Name), …)` is set 0's resource
// `Name`, numbered from the declarations it finds, `build/scene_set.rs`). Every header that
// declares a scene-set resource includes this one.
#ifndef MEADOW_PROFILE_GLSL
#define MEADOW_PROFILE_GLSL
#include "common/common.glsl"
#include "generated/scene_set.glsl"

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
//   `visible_entry`, `ground_texel`, `level_word`, the cull's verdicts and depth pyramid): a
//   vector gather on llvmpipe instead of a load per SIMD lane and word (`vk::buffer::TexelView`).
#if defined(MEADOW_PROFILE_LAVAPIPE)
#define TEXEL_TWINS
#elif !defined(MEADOW_PROFILE_GENERIC)
#error "build.rs defines MEADOW_PROFILE_LAVAPIPE or MEADOW_PROFILE_GENERIC"
#endif

#endif
