#version 460
#extension GL_GOOGLE_include_directive : require
// Test shader: `height_six` (lighting.glsl), the l^6 a strip level of a blade drawn with fewer
// segments than its model is lit with, at every level of strips of 1 to MODEL segments.
#include "common/common.glsl"
#include "common/lighting.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 0, std430) writeonly buffer Probe { float probe[]; };

// The model's segment count the probe's strips are coarser than (or equal to).
const uint MODEL = 16u;

void main() {
    // Levels 0..=s of each strip of s = 1..=MODEL segments, one after the other.
    uint at = 0u;
    for (uint s = 1u; s <= MODEL; s++) {
        for (uint level = 0u; level <= s; level++) {
            probe[at] = height_six(float(level) / float(s), s, MODEL);
            at++;
        }
    }
}
