#version 460
#extension GL_GOOGLE_include_directive : require
// A block field's terrain grid (terrain.vert's FIELD_TERRAIN_CELLS² cells around O): the relief's
// height and normal at every vertex, once per frame (`render::passes::relief_grid`), for the terrain, the
// cull's root heights and the blades' terrain normal (field.glsl: `relief_vertex`,
// `field_ground_height`, `field_ground_normal`). Vertex v lies at v * step + offset relative to O.
#define RELIEF_GRID_WRITER
#include "bindings.glsl"
#include "field.glsl"

layout(local_size_x = RELIEF_GROUP) in;

void main() {
    uint n = FIELD_TERRAIN_CELLS + 1u;
    uint i = gl_GlobalInvocationID.x;
    if (i >= n * n) {
        return;
    }
    vec2 p = vec2(uvec2(i % n, i / n)) * frame.terrain.x + terrain_grid_offset();
    relief_grid[i] = vec4(relief_height(p), relief_normal(p));
}
