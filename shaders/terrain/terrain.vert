#version 460
#extension GL_GOOGLE_include_directive : require
// Terrain by vertex pulling, indexed: vertex v is grid vertex (v % (cells + 1), v / (cells + 1)),
// heights from a storage buffer (a block field's from a level of its clipmap, relief_grid.comp); the
// index buffer splits each cell (0,0)-(1,0)-(1,1) and
// (0,0)-(1,1)-(0,1), as `scene::terrain::Terrain::height_at` (`render::terrain_chunks::chunked_indices`).
#include "common/bindings.glsl"
#include "common/field.glsl"

#include "common/lighting.glsl"

// Lit and fogged per vertex (Gouraud): the ground's normal and its distance vary slowly over a
// cell, and most of the ground ends up under grass, so the fragment shader only encodes the
// interpolated colour (per pixel, lighting and fog cost the terrain pass about a third of its
// time on llvmpipe).
layout(location = 0) out vec3 out_color;

// Ground under the grass: earthy green, Lambert plus sky ambient, fogged like the blades.
vec3 ground_color(vec3 normal, vec3 world) {
    vec3 n = normalize(normal);
    vec3 albedo = vec3(0.07, 0.085, 0.03);
    float lambert = max(dot(n, frame.sun_direction.xyz), 0.0);
    vec3 color = albedo * (vec3(0.35, 0.38, 0.45) + vec3(1.2, 1.1, 0.95) * lambert);
    return apply_fog(color, world, frame.camera_position, frame.sky_color);
}


float height(int x, int z) {
    int n = int(frame.params.z) + 1;
    x = clamp(x, 0, n - 1);
    z = clamp(z, 0, n - 1);
    return heights[z * n + x];
}

void main() {
    uint cells = frame.params.z;
    uvec2 grid = uvec2(uint(gl_VertexIndex) % (cells + 1u), uint(gl_VertexIndex) / (cells + 1u));
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        // A block field: level gl_InstanceIndex of the ground's clipmap (`render::ground_clipmap`),
        // FIELD_TERRAIN_CELLS² cells on the world's lattice of the level's step; the terrain pass
        // draws its chunks but the finer level's. relief_grid.comp filled the vertex when it
        // entered the window; `ground_vertex` applies the morph onto the next level's mesh.
        uint level = uint(gl_InstanceIndex);
        vec4 relief = ground_vertex(level, ivec2(grid));
        vec2 p = vec2(grid) * ground_level_step(level) + ground_level_offset(level);
        vec3 world = vec3(p.x, relief.x, p.y);
        out_color = ground_color(relief.yzw, world);
        gl_Position = frame.view_proj * vec4(world, 1.0);
        return;
    }
    int x = int(grid.x);
    int z = int(grid.y);
    float step = frame.terrain.y;
    vec3 world = vec3(frame.terrain.x + float(x) * step, height(x, z), frame.terrain.x + float(z) * step);
    // Smooth normal from central differences.
    float dx = height(x + 1, z) - height(x - 1, z);
    float dz = height(x, z + 1) - height(x, z - 1);
    out_color = ground_color(vec3(-dx, 2.0 * step, -dz), world);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
