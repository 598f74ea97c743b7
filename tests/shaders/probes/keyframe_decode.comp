#version 460
#extension GL_GOOGLE_include_directive : require
// Test: decodes every stored keyframe through `kf_fetch` (keyframes.glsl, the vertex shader's
// decoder) from the real keyframe texture or uniform array, for comparison with the CPU decode.
#include "common/common.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
layout(set = 0, binding = 1) uniform sampler2D keyframe_texture;
layout(constant_id = SPEC(KEYFRAME_UVEC4S)) const uint KEYFRAME_UVEC4S = 4096u;
layout(set = 0, binding = 2, std140) uniform KeyframeWords { uvec4 keyframe_words[KEYFRAME_UVEC4S]; };
layout(set = 0, binding = 3, std430) writeonly buffer Decoded { vec4 decoded[]; };

#include "animation/keyframes.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint segments = frame.params.x;
    uint count = frame.keyframes.x * frame.keyframes.y * segments;
    if (i >= count) {
        return;
    }
    decoded[i] = kf_fetch(i / segments, i % segments + 1u);
}
