// Set 0: the blade outline's alpha texture (`scene::alpha`), owned by `render::scene_gpu::SceneGpu`.
#ifndef MEADOW_BLADE_ALPHA_GLSL
#define MEADOW_BLADE_ALPHA_GLSL
#include "common/profile.glsl"

layout(SCENE(blade_alpha)) uniform sampler2D blade_alpha;

#endif
