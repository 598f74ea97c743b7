// Set 0: a stored field's terrain heights, `(cells + 1)²` floats, owned by
// `render::scene_gpu::SceneGpu`.
#ifndef MEADOW_HEIGHTS_GLSL
#define MEADOW_HEIGHTS_GLSL
#include "common/profile.glsl"

layout(SCENE(Heights), std430) readonly buffer Heights { float heights[]; };

#endif
