#version 460
#extension GL_GOOGLE_include_directive : require
// Terrain by vertex pulling: 6 vertices per grid cell, heights from a storage buffer. Cell split
// (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1), as `scene::terrain::Terrain::height_at`.
#include "bindings.glsl"
#include "field.glsl"

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_world;

const uvec2 CORNERS[6] = uvec2[6](uvec2(0, 0), uvec2(1, 0), uvec2(1, 1), uvec2(0, 0), uvec2(1, 1), uvec2(0, 1));

float height(int x, int z) {
    int n = int(frame.params.z) + 1;
    x = clamp(x, 0, n - 1);
    z = clamp(z, 0, n - 1);
    return heights[z * n + x];
}

void main() {
    uint cells = frame.params.z;
    uint cell = uint(gl_VertexIndex) / 6u;
    uvec2 grid = uvec2(cell % cells, cell / cells) + CORNERS[uint(gl_VertexIndex) % 6u];
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        // A block field: a grid of FIELD_TERRAIN_CELLS² cells centred on O's cell, evaluated on
        // the relief, its cell edge (terrain.x) a divisor or multiple of the block edge so the
        // lattice stays put when O moves by a block.
        float step = frame.terrain.x;
        vec2 p = (vec2(grid) - vec2(0.5 * float(cells))) * step + vec2(0.5 * frame.field.x);
        out_normal = relief_normal(p);
        out_world = vec3(p.x, relief_height(p), p.y);
        gl_Position = frame.view_proj * vec4(out_world, 1.0);
        return;
    }
    int x = int(grid.x);
    int z = int(grid.y);
    float step = frame.terrain.y;
    vec3 world = vec3(frame.terrain.x + float(x) * step, height(x, z), frame.terrain.x + float(z) * step);
    // Smooth normal from central differences.
    float dx = height(x + 1, z) - height(x - 1, z);
    float dz = height(x, z + 1) - height(x, z - 1);
    out_normal = normalize(vec3(-dx, 2.0 * step, -dz));
    out_world = world;
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
