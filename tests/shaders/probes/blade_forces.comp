#version 460
#extension GL_GOOGLE_include_directive : require
// Evaluates `blade_force` (shaders/animation/forces.glsl, the function the blade vertex shader uses) for
// every blade and writes it out: GPU read-back of per-blade forces for tests and experiments.
#include "common/common.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1, std430) readonly buffer Blades { BladeInstance blades[]; };
layout(set = 0, binding = 2, std430) readonly buffer Clusters { BladeCluster clusters[]; };
layout(set = 0, binding = 3, std430) readonly buffer Corners { vec4 corners[]; };
layout(set = 0, binding = 4, std430) readonly buffer Emitters { vec4 emitters[]; };
layout(set = 0, binding = 5, std430) writeonly buffer Forces { vec2 forces[]; };

#include "animation/forces.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(blades.length())) {
        return;
    }
    forces[i] = blade_force(i, blades[i]);
}
