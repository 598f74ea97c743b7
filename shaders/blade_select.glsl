// The keyframe selection of one blade from its force (shared by blade.vert and
// blade_pose.comp): force interpolated and attenuated (forces.glsl), divided by the blade's
// stiffness, expressed in the blade's frame, selected (keyframes.glsl).
#ifndef MEADOW_BLADE_SELECT_GLSL
#define MEADOW_BLADE_SELECT_GLSL
#include "forces.glsl"
#include "keyframes.glsl"

// The selection of a blade from its force (shared by blade.vert and blade_pose.comp).
KfSelection kf_select_blade(uint blade_index, BladeInstance blade, out float force_magnitude) {
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    vec2 force = blade_force(blade_index, blade.position.xz) / blade.stiffness;
    force_magnitude = length(force);
    return kf_select(vec2(dot(force, across.xz), dot(force, normal_dir.xz)));
}

#endif
