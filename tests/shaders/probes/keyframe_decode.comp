#version 460
#extension GL_GOOGLE_include_directive : require
// Test: decodes every stored keyframe through `kf_fetch` (keyframes.glsl, the vertex shader's
// decoder) from the real keyframe texture or uniform array, for comparison with the CPU decode.
#include "common/common.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std140) uniform Frame { FrameUniforms frame; };
// The keyframe response's resources (texture, uniform array, shape) at bindings 1-3 of set 0.
#define KEYFRAME_SET 0
#define KEYFRAME_BINDING 1
#include "animation/keyframes.glsl"
layout(set = 0, binding = 4, std430) writeonly buffer Decoded { vec4 decoded[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint segments = frame.params.x;
    uint count = keyframe_shape.x * keyframe_shape.y * segments;
    if (i >= count) {
        return;
    }
    decoded[i] = kf_fetch(i / segments, i % segments + 1u);
}
