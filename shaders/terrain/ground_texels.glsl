// Set 0: the ground's clipmap (`GroundTexels`, its texel view `ground_texels` under the lavapipe
// profile), allocated by `render::scene_gpu::SceneGpu` for its ground source (`render::ground`):
// a stored terrain's grid, uploaded once, or a block field's relief levels, filled as the camera
// moves by `render::passes::ground_fill`. Read through common/ground.glsl.
#ifndef MEADOW_GROUND_TEXELS_GLSL
#define MEADOW_GROUND_TEXELS_GLSL
#include "common/profile.glsl"

// Per vertex of a level, in the slot of its vertex (a camera grid, camera_grid.glsl): x its
// height, y the height of the next level's mesh there, zw the ground's rise along x and z over
// the level's `ground_level_rise_run` metres (the normal is (-z, run, -w)).
// And per vertex, in the same slot, the ground's cover (`scene::cover`): the densities grass
// (low half) and flowers (high half, `scene::flowers`) grow at there, two unorm16 in [0, 1].
// After every level's vertices, per level its tiles (`render::ground::tiles`): GROUND_TILE_CELLS²
// cells each, row by row from the window's first vertex, x the lowest height of its vertices, y
// the highest, z the most grass cover and w the most flower cover at them. Written by
// terrain/ground_tiles.comp (GROUND_TILER: the vertices read, the tiles written) after a fill.
#ifdef GROUND_WRITER
layout(SCENE(GroundTexels), std430) writeonly buffer GroundTexels { vec4 ground_grid[]; };
layout(SCENE(GroundCover), std430) writeonly buffer GroundCover { uint ground_cover_grid[]; };
#elif defined(GROUND_TILER)
layout(SCENE(GroundTexels), std430) buffer GroundTexels { vec4 ground_grid[]; };
vec4 ground_texel(int i) {
    return ground_grid[i];
}
layout(SCENE(GroundCover), std430) readonly buffer GroundCover { uint ground_cover_grid[]; };
vec2 ground_cover_texel(int i) {
    return unpackUnorm2x16(ground_cover_grid[i]);
}
#elif defined(TEXEL_TWINS)
layout(SCENE(ground_texels)) uniform samplerBuffer ground_texels;
vec4 ground_texel(int i) {
    return texelFetch(ground_texels, i);
}
layout(SCENE(ground_cover_texels)) uniform usamplerBuffer ground_cover_texels;
vec2 ground_cover_texel(int i) {
    return unpackUnorm2x16(texelFetch(ground_cover_texels, i).x);
}
#else
layout(SCENE(GroundTexels), std430) readonly buffer GroundTexels { vec4 ground_grid[]; };
vec4 ground_texel(int i) {
    return ground_grid[i];
}
layout(SCENE(GroundCover), std430) readonly buffer GroundCover { uint ground_cover_grid[]; };
vec2 ground_cover_texel(int i) {
    return unpackUnorm2x16(ground_cover_grid[i]);
}
#endif

#endif
