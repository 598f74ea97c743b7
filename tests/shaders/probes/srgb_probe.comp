#version 460
#extension GL_GOOGLE_include_directive : require
// Test shader: `encode_output` (lighting.glsl), the sRGB transfer of the UNORM targets, at
// SRGB_PROBE_VALUES evenly spaced linear values from 0 to 1.
#include "common/common.glsl"
#include "common/lighting.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) writeonly buffer Probe { float probe[]; };

const uint SRGB_PROBE_VALUES = 4096u; // tests/lighting.rs

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < SRGB_PROBE_VALUES) {
        probe[i] = encode_output(vec3(float(i) / float(SRGB_PROBE_VALUES - 1u))).x;
    }
}
