#version 460
#extension GL_GOOGLE_include_directive : require
// The ground's tiles (`render::ground::tiles`), the last step of a fill (`render::passes::
// ground_fill`): for every tile of each level whose window moved this frame (or of every level,
// at a refill), the lowest and highest height of its vertices' texels (their own and the next
// level's mesh there, between which a drawn vertex slides) and the most grass and flower cover at
// them. The cull bounds a block cell's heights by them and skips a cell with no cover
// (common/ground.glsl: `ground_tile_bounds`). Tiles are counted from each window's first vertex,
// and a window holds whole tiles (`FIELD_TERRAIN_CELLS` is a multiple of GROUND_TILE_CELLS), so a
// moved level's tiles are all written anew: 1 600 of 9 texels each.
#define GROUND_TILER
#include "common/bindings.glsl"
#include "common/ground.glsl"

layout(local_size_x = CAMERA_GRID_GROUP) in;

// `render::passes::ground_fill::TilesPush`: the levels to tile, and how many. Invocations past
// them tile the last one again (the same values written twice): nothing here branches on the
// push constants (camera_grid.glsl says why).
layout(push_constant) uniform Tiles {
    uvec4 levels[4]; // the levels, four a vector
    uvec4 count;     // x how many, y tiles per level
} tiling;

void main() {
    uint per = tiling.count.y;
    uint i = min(gl_GlobalInvocationID.x, tiling.count.x * per - 1u);
    uint k = i / per;
    uint level = tiling.levels[k / 4u][k % 4u];
    uint t = ground_tiles_per_side();
    uvec2 tile = uvec2((i % per) % t, (i % per) / t);
    ground_grid[ground_tile_texel(level, tile)] = ground_tile_of(ground_level(level, ground_shape()), tile);
}
