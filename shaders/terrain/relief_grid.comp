#version 460
#extension GL_GOOGLE_include_directive : require
// A block field's terrain grid (terrain.vert's FIELD_TERRAIN_CELLS² cells around O), a camera
// grid (`render::camera_grid`, one level of (FIELD_TERRAIN_CELLS + 1)² vertices on the world's
// lattice of the grid's step): the vertices that entered the window since the last fill
// (`render::passes::relief_grid`), each with what depends on its place in the world alone: the
// relief's height, the coarse mesh's height there and the relief's normal. Readers apply the
// camera-relative morph between the two heights (common/field.glsl: `relief_vertex`,
// `field_ground_height`, `field_ground_normal`). Local vertex v lies at v * step + offset
// relative to O.
#define RELIEF_GRID_WRITER
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/camera_grid.glsl"

layout(local_size_x = CAMERA_GRID_GROUP) in;

layout(push_constant) uniform Fill {
    CameraGridFill fill;
};

void main() {
    uvec3 local = camera_grid_entered(fill, gl_GlobalInvocationID.x);
    uvec2 v = local.xz;
    float step = frame.terrain.x;
    vec2 p = vec2(v) * step + terrain_grid_offset();
    float h = relief_height(p);
    // The far terrain (`render::terrain_chunks`) draws cells of two steps: the coarse mesh's
    // height at an odd vertex is the mean of the two even vertices of the coarse edge along x or
    // z, or of the coarse cell's diagonal, that it halves (split (0,0)-(1,1) like the fine
    // cells). The grid keeps its vertex 0 on the coarse lattice (`terrain_grid_offset`), so a
    // vertex's parity is its place in the world's.
    float coarse = h;
    uvec2 odd = v & 1u;
    if (terrain_coarsens() && (odd.x | odd.y) != 0u) {
        vec2 across = vec2(odd) * step;
        coarse = 0.5 * (relief_height(p - across) + relief_height(p + across));
    }
    // A normal's y is above 0: x and z say it (`relief_vertex` rebuilds y).
    vec3 n = relief_normal(p);
    uvec3 dims = fill.dims.xyz;
    relief_grid[camera_grid_slot(local, fill.base.xyz, dims)] = vec4(h, coarse, n.x, n.z);
}
