#version 460
#extension GL_GOOGLE_include_directive : require
// Test shader: reads every field of every BladeInstance through the std430 declaration in
// common.glsl and writes them as 8 words, so the test can compare them with what Rust wrote.
#include "common/common.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) readonly buffer Blades { BladeInstance blades[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Fields { uint fields[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(blades.length())) {
        return;
    }
    BladeInstance b = blades[i];
    uint o = i * 8u;
    fields[o + 0u] = floatBitsToUint(b.position.x);
    fields[o + 1u] = floatBitsToUint(b.position.y);
    fields[o + 2u] = floatBitsToUint(b.position.z);
    fields[o + 3u] = floatBitsToUint(b.facing);
    fields[o + 4u] = floatBitsToUint(b.height);
    fields[o + 5u] = floatBitsToUint(b.width);
    fields[o + 6u] = floatBitsToUint(b.stiffness);
    fields[o + 7u] = b.variation;
}
