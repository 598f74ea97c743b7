#version 460
#extension GL_GOOGLE_include_directive : require
// Test: the keyframe selection and smoothing of the renderer, run for a buffer of forces. Each
// force (fx, fz) is already in the blade's frame and divided by its stiffness, as
// `kf_select_blade` (blade_select.glsl) hands it to `kf_select`; every chain level is then blended
// by `kf_level`, as `deformed` calls it for blade.vert and blade_pose.comp (MODEL_SEGMENTS
// levels, the vertex representation). The keyframe resources and the specialization
// constants are the renderer's response's; the test compares the levels with
// `keyframes::table::KeyframeTable::pose_for`, the CPU code the pose-error report measures.
#include "common/common.glsl"

layout(local_size_x = 64) in;

// Set 0 is the test's own, numbered here.
layout(set = SET_SCENE, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = SET_SCENE, binding = 1, std430) readonly buffer Forces { vec2 forces[]; };
// Per force, MODEL_SEGMENTS + 1 levels: root-relative point of the unit blade (xyz), twist (w).
layout(set = SET_SCENE, binding = 2, std430) writeonly buffer Levels { vec4 levels[]; };
// Set 1: the keyframe response's own resources, as keyframes.glsl declares them, given by the
// response by name (`render::animation::keyframed::KeyframeResponse::resources`).
#define KEYFRAME_SET 1
#define KEYFRAME_BINDING 0
#include "animation/keyframes.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(forces.length())) {
        return;
    }
    KfSelection sel = kf_select(forces[i]);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        levels[i * (MODEL_SEGMENTS + 1u) + level] = kf_level(sel, level, MODEL_SEGMENTS);
    }
}
