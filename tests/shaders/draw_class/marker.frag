#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the markers' flat red, encoded for the target.
#include "common/bindings.glsl"
#include "common/lighting.glsl"

layout(location = 0) in vec3 in_color;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(encode_output(in_color), 1.0);
}
