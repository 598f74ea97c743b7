// Set 0: a block field's terrain grid (`ReliefGrid`, its texel view `relief_texels` under the
// lavapipe profile), allocated by `render::scene_gpu::SceneGpu`, filled by
// `render::passes::relief_grid`.
#ifndef MEADOW_RELIEF_GRID_GLSL
#define MEADOW_RELIEF_GRID_GLSL
#include "common/profile.glsl"

// A block field's terrain grid (FIELD_TERRAIN_CELLS² cells around O, field.glsl's
// `terrain_grid_offset`), a camera grid (camera_grid.glsl): per vertex, in the slot of its world
// vertex, the relief's height, the coarse mesh's height there and the relief's normal (x, z),
// filled as vertices enter the window by relief_grid.comp; the terrain, the cull and the blades'
// lighting read it (field.glsl, `relief_vertex`) instead of summing the relief's waves per
// vertex, blade and level.
#ifdef RELIEF_GRID_WRITER
layout(SCENE(ReliefGrid), std430) writeonly buffer ReliefGrid { vec4 relief_grid[]; };
#elif defined(TEXEL_TWINS)
layout(SCENE(relief_texels)) uniform samplerBuffer relief_texels;
vec4 relief_texel(int i) {
    return texelFetch(relief_texels, i);
}
#else
layout(SCENE(ReliefGrid), std430) readonly buffer ReliefGrid { vec4 relief_grid[]; };
vec4 relief_texel(int i) {
    return relief_grid[i];
}
#endif

#endif
