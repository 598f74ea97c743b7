#version 460
#extension GL_GOOGLE_include_directive : require
// A run-once test pass with its own camera (tests/bake_camera.rs): projects points through the
// frame uniforms of its own set-0 instance (`render::renderer::extensions::FrameInstance`), which
// hold an orthographic camera, not the main one. Set 0 is the library's (common/bindings.glsl:
// only `frame` is read, so only that binding counts); set 1 is the pass's own, reflected.
#include "common/bindings.glsl"

layout(local_size_x = 64) in;

layout(set = 1, binding = 0, std430) readonly buffer Points { vec4 points[]; };
layout(set = 1, binding = 1, std430) writeonly buffer Projected { vec4 projected[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < uint(points.length())) {
        projected[i] = frame.view_proj * points[i];
    }
}
