#version 460
#extension GL_GOOGLE_include_directive : require
// Debug view of the cluster bounds (`--debug-view bounds`, `render::passes::cluster_bounds`):
// the edges of every force cluster (thesis 3.2.2) as lines lifted above the ground, one segment
// between two neighbouring corners per pair of vertices (no vertex buffer). Each end is coloured
// by the force at its corner this frame, from yellow (none) to red (the strongest poses).
#include "common/bindings.glsl"
#include "wind/wind_field.glsl"
#include "common/ground.glsl"

layout(push_constant) uniform Grid {
    float origin;        // x = z of corner 0
    float cluster_size;  // m
    uint corners;        // per side
    float lift;          // m above the terrain
} grid;

layout(location = 0) out vec3 out_color;

void main() {
    uint n = grid.corners;
    uint segment = uint(gl_VertexIndex) / 2u;
    uint per_direction = n * (n - 1u);
    bool along_z = segment >= per_direction;
    uint s = segment % per_direction;
    uint line = s / (n - 1u);
    uint step = s % (n - 1u) + (uint(gl_VertexIndex) & 1u);
    uvec2 corner = along_z ? uvec2(line, step) : uvec2(step, line);
    vec2 p = grid.origin + vec2(corner) * grid.cluster_size;
    vec3 world = vec3(p.x, ground_height(p) + grid.lift, p.y);
    float force = length(wind_corner(corner.y * n + corner.x).xz) / KEYFRAME_WIND_SCALE;
    out_color = mix(vec3(1.0, 0.9, 0.1), vec3(0.9, 0.05, 0.02), clamp(force, 0.0, 1.0));
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
