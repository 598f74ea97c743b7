#version 460
#extension GL_GOOGLE_include_directive : require
// The debug views' lines (the cluster bounds, the wind's arrows): the colour the vertex shader
// gave, encoded like every other pass's output.
#include "common/bindings.glsl"
#include "common/lighting.glsl"

layout(location = 0) in vec3 in_color;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(encode_output(in_color), 1.0);
}
