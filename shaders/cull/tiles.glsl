// Set 0: the tiles (`BladeTile`, `scene::tiles`), owned by `render::scene_gpu::SceneGpu`.
#ifndef MEADOW_TILES_GLSL
#define MEADOW_TILES_GLSL
#include "common/profile.glsl"

layout(SCENE(Tiles), std430) readonly buffer Tiles { BladeTile tiles[]; };

#endif
