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
// Per-blade variation; its spare top byte carries the force magnitude / stiffness for the debug
// view (a separate flat varying costs ~25 % of the blade pass on llvmpipe).
layout(location = 3) flat out uint out_variation;

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
    float force_magnitude = 0.0;
    if (ANIMATION_MODE == MODE_STATIC) {
        local = bezier_point(p[0], p[1], p[2], p[3], t);
        local_tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
    } else {
        float force;
        KfSelection sel;
        if ((RENDER_FLAGS & FLAG_EVAL_BLADE) != 0u) {
            // Selected once per blade by blade_pose.comp (thesis ch. 7 future work, with compute).
            sel = kf_unpack(poses[blade_index], force);
        } else {
            sel = kf_select_blade(blade_index, blade, force);
        }
        force_magnitude = force;
        if (REPRESENTATION == 1u) {
            // Curve representation: the pose's control points displace the neutral ones; the
            // blade is evaluated at any t, with an analytic tangent; the twist grows linearly.
            vec4 c1 = kf_record(sel, 1u, vec3(0.0, 1.0 / 3.0, 0.0));
            vec4 c2 = kf_record(sel, 2u, vec3(0.0, 2.0 / 3.0, 0.0));
            vec4 c3 = kf_record(sel, 3u, vec3(0.0, 1.0, 0.0));
            vec3 q1 = p[1] + (c1.xyz - vec3(0.0, 1.0 / 3.0, 0.0)) * blade.height;
            vec3 q2 = p[2] + (c2.xyz - vec3(0.0, 2.0 / 3.0, 0.0)) * blade.height;
            vec3 q3 = p[3] + (c3.xyz - vec3(0.0, 1.0, 0.0)) * blade.height;
            local = bezier_point(p[0], q1, q2, q3, t);
            local_tangent = bezier_tangent(p[0], q1, q2, q3, t);
            twist = c1.w * t;
        } else {
            vec4 here = deformed(p, sel, level, segments, blade.height);
            vec4 below = level > 0u ? deformed(p, sel, level - 1u, segments, blade.height) : here;
            vec4 above = level < segments ? deformed(p, sel, level + 1u, segments, blade.height) : here;
            local = here.xyz;
            local_tangent = above.xyz - below.xyz;
            twist = here.w;
        }
    }

    // The width turns about +y by the twist: the blade faces the wind (Zhang Xia §3.2.5).
    vec3 width_dir = across * cos(twist) - normal_dir * sin(twist);
    vec3 world = blade.position + across * local.x + vec3(0.0, local.y, 0.0) + normal_dir * local.z
        + width_dir * ((side - 0.5) * blade.width);
    vec3 world_tangent = across * local_tangent.x + vec3(0.0, local_tangent.y, 0.0) + normal_dir * local_tangent.z;

    out_uv = vec2(side, t);
    out_normal = normalize(cross(width_dir, world_tangent));
    out_world = world;
    out_variation = (blade.variation & 0x00ffffffu) | (uint(round(clamp(force_magnitude, 0.0, 1.0) * 255.0)) << 24);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
