#version 460
#extension GL_GOOGLE_include_directive : require
// A block field's terrain grid (terrain.vert's FIELD_TERRAIN_CELLS² cells around O): the relief's
// height and normal at every vertex, once per frame (`render::passes::relief_grid`), for the terrain, the
// cull's root heights and the blades' terrain normal (field.glsl: `relief_vertex`,
// `field_ground_height`, `field_ground_normal`). Vertex v lies at v * step + offset relative to O.
#define RELIEF_GRID_WRITER
#include "common/bindings.glsl"
#include "common/field.glsl"

layout(local_size_x = RELIEF_GROUP) in;

void main() {
    uint n = FIELD_TERRAIN_CELLS + 1u;
    uint i = gl_GlobalInvocationID.x;
    if (i >= n * n) {
        return;
    }
    uvec2 v = uvec2(i % n, i / n);
    float step = frame.terrain.x;
    vec2 p = vec2(v) * step + terrain_grid_offset();
    float h = relief_height(p);
    // The far terrain (`render::terrain_chunks`): from TERRAIN_MORPH_CELLS to TERRAIN_FINE_CELLS
    // (Chebyshev, from the grid's centre) an odd vertex slides onto the coarse mesh of cells of
    // two steps, split (0,0)-(1,1) like the fine ones: the middle of the coarse edge along x or
    // z, or of the coarse cell's diagonal (`render::field_gpu::terrain_morph`). Past it the fine
    // grid is the coarse mesh, so fine and coarse chunks meet without cracks and the cull's
    // roots, interpolating this grid, sit on the terrain as drawn. The normal stays the relief's.
    uvec2 odd = v & 1u;
    if (terrain_coarsens() && (odd.x | odd.y) != 0u) {
        ivec2 d = abs(ivec2(v) - ivec2(FIELD_TERRAIN_CELLS / 2u));
        float band = float(TERRAIN_FINE_CELLS - TERRAIN_MORPH_CELLS);
        float k = clamp(float(max(d.x, d.y) - int(TERRAIN_MORPH_CELLS)) / band, 0.0, 1.0);
        if (k > 0.0) {
            vec2 across = vec2(odd) * step;
            h = mix(h, 0.5 * (relief_height(p - across) + relief_height(p + across)), k);
        }
    }
    relief_grid[i] = vec4(h, relief_normal(p));
}
