#version 460
#extension GL_GOOGLE_include_directive : require
// Test shader: evaluates Belyaev's Fresnel term (lighting.glsl) at the strip vertices of static
// blades through the functions blade.vert uses (the neutral Bézier, the terrain normal under the
// root), and writes each vertex with its inputs so the test can evaluate the formula on the CPU.
#include "common/common.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) readonly buffer Blades { BladeInstance blades[]; };
layout(set = 0, binding = 1, std430) readonly buffer Heights { float heights[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Probe { float probe[]; };
// camera xyz; grid origin, cell edge, cells per side; strip vertices per blade.
layout(push_constant) uniform Params { vec4 camera; vec4 grid; uint vertices; } params;

#include "common/bezier.glsl"
#include "common/lighting.glsl"
#include "common/ground_patch.glsl"

const uint PROBE_FLOATS = 10u;

// The ground's normal under `xz` as common/ground.glsl gives it for a stored terrain's one level
// (its cell, clamped to the grid, and the bilinear patch through its heights).
vec3 grid_normal(vec2 xz, float origin, float step, uint cells) {
    vec2 g = (xz - vec2(origin)) / step;
    ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(int(cells) - 1));
    vec2 f = clamp(g - vec2(c), vec2(0.0), vec2(1.0));
    uint i = uint(c.y) * (cells + 1u) + uint(c.x);
    uint n = cells + 1u;
    vec4 h = vec4(heights[i], heights[i + 1u], heights[i + n], heights[i + n + 1u]);
    return bilinear_patch_normal(f, h, step);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint blade_index = i / params.vertices;
    if (blade_index >= uint(blades.length())) {
        return;
    }
    uint v = i % params.vertices;
    uint segments = params.vertices / 2u - 1u;
    BladeInstance blade = blades[blade_index];
    float t = float(v / 2u) / float(segments);
    float side = float(v & 1u);
    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    vec3 local = bezier_point(p[0], p[1], p[2], p[3], t);
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    vec3 world = blade.position + across * (local.x + (side - 0.5) * blade.width) + vec3(0.0, local.y, 0.0)
        + normal_dir * local.z;
    vec3 terrain_normal = grid_normal(blade.position.xz, params.grid.x, params.grid.y, uint(params.grid.z));
    vec3 fresnel = blade_fresnel(terrain_normal, normalize(params.camera.xyz - world), t);
    uint o = i * PROBE_FLOATS;
    probe[o + 0u] = world.x;
    probe[o + 1u] = world.y;
    probe[o + 2u] = world.z;
    probe[o + 3u] = t;
    probe[o + 4u] = terrain_normal.x;
    probe[o + 5u] = terrain_normal.y;
    probe[o + 6u] = terrain_normal.z;
    probe[o + 7u] = fresnel.r;
    probe[o + 8u] = fresnel.g;
    probe[o + 9u] = fresnel.b;
}
