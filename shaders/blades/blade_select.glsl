// The keyframe selection of one blade from its force (shared by blade.vert and
// blade_pose.comp): force interpolated and attenuated (forces.glsl), divided by the blade's
// stiffness, expressed in the blade's frame, selected (keyframes.glsl).
#ifndef MEADOW_BLADE_SELECT_GLSL
#define MEADOW_BLADE_SELECT_GLSL
#include "common/bezier.glsl"
#include "animation/forces.glsl"
#include "animation/keyframes.glsl"

// The selection of a blade from its force (shared by blade.vert and blade_pose.comp).
KfSelection kf_select_blade(uint blade_index, BladeInstance blade, out float force_magnitude) {
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    vec2 force = blade_force(blade_index, blade) / blade.stiffness;
    force_magnitude = length(force);
    return kf_select(vec2(dot(force, across.xz), dot(force, normal_dir.xz)));
}

// Local-frame point of the deformed blade at `level`: neutral Bézier point plus the keyframe
// displacement (root-relative pose minus the straight unit blade) scaled by the height. w: twist.
vec4 deformed(vec3 p[4], KfSelection sel, uint level, uint segments, float height) {
    float t = float(level) / float(segments);
    vec4 pose = kf_level(sel, level, segments);
    vec3 displacement = pose.xyz - vec3(0.0, t, 0.0);
    return vec4(bezier_point(p[0], p[1], p[2], p[3], t) + displacement * height, pose.w);
}

// Curve representation: the pose's control points displace the neutral ones (w: twist at the
// tip for c1; the twist grows linearly along the blade).
void curve_controls(KfSelection sel, vec3 p[4], float height, out vec4 c1, out vec4 c2, out vec4 c3) {
    vec4 k1 = kf_record(sel, 1u, vec3(0.0, 1.0 / 3.0, 0.0));
    vec4 k2 = kf_record(sel, 2u, vec3(0.0, 2.0 / 3.0, 0.0));
    vec4 k3 = kf_record(sel, 3u, vec3(0.0, 1.0, 0.0));
    c1 = vec4(p[1] + (k1.xyz - vec3(0.0, 1.0 / 3.0, 0.0)) * height, k1.w);
    c2 = vec4(p[2] + (k2.xyz - vec3(0.0, 2.0 / 3.0, 0.0)) * height, k2.w);
    c3 = vec4(p[3] + (k3.xyz - vec3(0.0, 1.0, 0.0)) * height, k3.w);
}

#endif
