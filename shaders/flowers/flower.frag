#version 460
#extension GL_GOOGLE_include_directive : require
// The flowers' pass (`render::flowers`): lit per vertex (flower.vert), the fog's sky added and the
// colour encoded for the target. Opaque geometry, no alpha test: early depth rejects what nearer
// blades and flowers hide.
#include "common/bindings.glsl"
#include "common/lighting.glsl"

layout(location = 0) in vec4 in_lit;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(encode_output(in_lit.rgb + frame.sky_color.rgb * (1.0 - in_lit.a)), 1.0);
}
