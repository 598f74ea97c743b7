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
#include "lighting.glsl"

// Lit per vertex (Gouraud): the blade's colour is affine along its length and its normal is the
// same across its width, so the fragment shader only adds the alpha-tested rim. Every varying
// costs llvmpipe setup and interpolation per triangle: four floats of light and fog replace the
// normal, world position and flat variation (ten components, 1.3-1.5x the floor's frame time).
// Per-cluster draws (`render::submission::ClusterPush`, Pelzer §7.4.2): the cluster's first
// blade; instance i of the draw is blade first_blade + i.
layout(push_constant) uniform ClusterPush {
    uint first_blade;
} cluster_push;

layout(location = 0) out vec2 out_uv;         // u across, v root -> tip
layout(location = 1) out vec4 out_lit;        // rgb: lit, fogged blade colour before the rim; a: fog transmittance

// Local-frame point of the deformed blade at `level`: neutral Bézier point plus the keyframe
// displacement (root-relative pose minus the straight unit blade) scaled by the height. w: twist.
vec4 deformed(vec3 p[4], KfSelection sel, uint level, uint segments, float height) {
    float t = float(level) / float(segments);
    vec4 pose = kf_level(sel, level, segments);
    vec3 displacement = pose.xyz - vec3(0.0, t, 0.0);
    return vec4(bezier_point(p[0], p[1], p[2], p[3], t) + displacement * height, pose.w);
}

void main() {
    const uint segments = SEGMENTS;
    uint blade_index = uint(gl_InstanceIndex) * BLADES_PER_INSTANCE + uint(gl_VertexIndex) / STRIP_STRIDE;
    if ((RENDER_FLAGS & FLAG_CLUSTER_PUSH) != 0u) {
        blade_index += cluster_push.first_blade;
    }
    if (BLADES_PER_INSTANCE > 1u && blade_index >= frame.params.y) {
        // Tail of the last instance: a degenerate point outside the clip volume.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        out_uv = vec2(0.0);
        out_lit = vec4(0.0);
        return;
    }
    uint j = uint(gl_VertexIndex) % STRIP_STRIDE;
    uint strip = min(uint(max(int(j) - int(STRIP_LEAD), 0)), 2u * segments + 1u);
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

    // Diffuse colour, darker at the root and brighter towards the tip (thesis 4.1).
    float hue = unpack_variation(blade.variation, 0);
    float brightness = 0.75 + 0.5 * unpack_variation(blade.variation, 1);
    vec3 root_color = mix(vec3(0.045, 0.12, 0.02), vec3(0.08, 0.13, 0.02), hue);
    vec3 tip_color = mix(vec3(0.22, 0.42, 0.06), vec3(0.42, 0.45, 0.10), hue);
    vec3 diffuse = mix(root_color, tip_color, t) * brightness;
    if ((RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        // Debug view: force magnitude from green (none) to red (the table's strongest pose).
        diffuse = mix(vec3(0.05, 0.25, 0.03), vec3(0.8, 0.02, 0.01), clamp(force_magnitude, 0.0, 1.0)) * mix(0.6, 1.0, t);
    }
    // Two-sided: light the side facing the viewer, decided from the view vector so the strip's
    // triangle parity cannot flip it. Belyaev §2.3 is linear in the diffuse colour, and so is the
    // fog: colour = lit * rim + sky * (1 - fog) in blade.frag.
    vec3 n = normalize(cross(width_dir, world_tangent));
    n = dot(n, frame.camera_position.xyz - world) < 0.0 ? -n : n;
    float fog = fog_transmittance(world, frame.camera_position, frame.sky_color);
    out_uv = vec2(side, t);
    out_lit = vec4(blade_radiance(diffuse, diffuse, n, frame.sun_direction.xyz, t) * fog, fog);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
