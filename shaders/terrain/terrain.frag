#version 460
#extension GL_GOOGLE_include_directive : require
// Ground under the grass: the colour terrain.vert lit, fogged and encoded for the target.
#include "common/bindings.glsl"
#include "common/lighting.glsl"

layout(location = 0) in vec3 in_color;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(in_color, 1.0);
}
