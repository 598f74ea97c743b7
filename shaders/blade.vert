#version 460
#extension GL_GOOGLE_include_directive : require
// Blades by vertex pulling: no vertex buffer. Each instance draws `batching.x` blades as one
// triangle strip; gl_InstanceIndex and gl_VertexIndex select the blade and its strip vertex.
// Strip vertex 2k + side lies on Bézier spline `side` at t = k / segments (thesis 4.1). Blades in
// an instance are joined by repeating their first and last vertices (degenerate triangles), see
// `scene::bezier::Batching`.
//
// Texture mode (thesis 4.4.1): the blade's force is interpolated from its cluster's corners
// (eq. 3.6), expressed in the blade's frame, and selects a pose of the keyframe texture; the
// pose's displacement (eq. 3.4/3.9), scaled by the blade's height, is added to the neutral
// Bézier blade, and the width turns by the pose's twist.
#include "bindings.glsl"
#include "bezier.glsl"
#include "forces.glsl"
#include "keyframes.glsl"
#include "blade_select.glsl"

layout(location = 0) out vec2 out_uv;         // u across, v root -> tip
layout(location = 1) out vec3 out_normal;     // world space
layout(location = 2) out vec3 out_world;
layout(location = 3) flat out uint out_variation;
layout(location = 4) flat out float out_force;   // force magnitude / stiffness (debug view)

// Local-frame point of the deformed blade at `level`: neutral Bézier point plus the keyframe
// displacement (root-relative pose minus the straight unit blade) scaled by the height. w: twist.
vec4 deformed(vec3 p[4], KfSelection sel, uint level, uint segments, float height) {
    float t = float(level) / float(segments);
    vec4 pose = kf_level(sel, level, segments);
    vec3 displacement = pose.xyz - vec3(0.0, t, 0.0);
    return vec4(bezier_point(p[0], p[1], p[2], p[3], t) + displacement * height, pose.w);
}

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
        out_force = 0.0;
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
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));

    vec3 local;
    vec3 local_tangent;
    float twist = 0.0;
    out_force = 0.0;
    if (frame.animation.x == MODE_STATIC) {
        local = bezier_point(p[0], p[1], p[2], p[3], t);
        local_tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
    } else {
        float force;
        KfSelection sel;
        if ((frame.batching.w & FLAG_EVAL_BLADE) != 0u) {
            // Selected once per blade by blade_pose.comp (thesis ch. 7 future work, with compute).
            sel = kf_unpack(poses[blade_index], force);
        } else {
            sel = kf_select_blade(blade_index, blade, force);
        }
        out_force = force;
        vec4 here = deformed(p, sel, level, segments, blade.height);
        vec4 below = level > 0u ? deformed(p, sel, level - 1u, segments, blade.height) : here;
        vec4 above = level < segments ? deformed(p, sel, level + 1u, segments, blade.height) : here;
        local = here.xyz;
        local_tangent = above.xyz - below.xyz;
        twist = here.w;
    }

    // The width turns about +y by the twist: the blade faces the wind (Zhang Xia §3.2.5).
    vec3 width_dir = across * cos(twist) - normal_dir * sin(twist);
    vec3 world = blade.position + across * local.x + vec3(0.0, local.y, 0.0) + normal_dir * local.z
        + width_dir * ((side - 0.5) * blade.width);
    vec3 world_tangent = across * local_tangent.x + vec3(0.0, local_tangent.y, 0.0) + normal_dir * local_tangent.z;

    out_uv = vec2(side, t);
    out_normal = normalize(cross(width_dir, world_tangent));
    out_world = world;
    out_variation = blade.variation;
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
