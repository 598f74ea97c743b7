#version 460
#extension GL_GOOGLE_include_directive : require
// Blades by vertex pulling: no vertex buffer. Each instance draws `batching.x` blades as one
// triangle strip; gl_InstanceIndex and gl_VertexIndex select the blade and its strip vertex.
// Strip vertex 2k + side lies on Bézier spline `side` at t = k / segments (thesis 4.1). Blades in
// an instance are joined by repeating their first and last vertices (degenerate triangles), see
// `scene::bezier::batched_vertex`.
#include "bindings.glsl"
#include "bezier.glsl"

layout(location = 0) out vec2 out_uv;         // u across, v root -> tip
layout(location = 1) out vec3 out_normal;     // world space
layout(location = 2) out vec3 out_world;
layout(location = 3) flat out uint out_variation;

void main() {
    uint segments = frame.params.x;
    uint per_blade = frame.batching.y;
    uint blade_index = uint(gl_InstanceIndex) * frame.batching.x + uint(gl_VertexIndex) / per_blade;
    if (blade_index >= frame.params.y) {
        // Tail of the last instance: a degenerate point outside the clip volume.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        out_uv = vec2(0.0);
        out_normal = vec3(0.0, 1.0, 0.0);
        out_world = vec3(0.0);
        out_variation = 0u;
        return;
    }
    uint j = uint(gl_VertexIndex) % per_blade;
    uint strip = min(uint(max(int(j) - int(frame.batching.z), 0)), 2u * segments + 1u);
    BladeInstance blade = blades[blade_index];
    uint level = strip >> 1;
    float side = float(strip & 1u);
    float t = float(level) / float(segments);

    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    vec3 local = bezier_point(p[0], p[1], p[2], p[3], t);
    vec3 tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);

    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    vec3 world = blade.position
        + across * (local.x + (side - 0.5) * blade.width)
        + vec3(0.0, local.y, 0.0)
        + normal_dir * local.z;
    vec3 world_tangent = across * tangent.x + vec3(0.0, tangent.y, 0.0) + normal_dir * tangent.z;

    out_uv = vec2(side, t);
    out_normal = normalize(cross(across, world_tangent));
    out_world = world;
    out_variation = blade.variation;
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
