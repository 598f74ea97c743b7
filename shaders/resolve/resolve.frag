#version 460
#extension GL_GOOGLE_include_directive : require
// `--msaa`: the resolve of the multisampled scene (`render::msaa`). Each pixel's samples hold
// linear radiance; they are clamped to the displayable range one by one (a bright sample must
// not bleed past its share), averaged in linear space, then encoded as the target needs
// (`encode_output`: sRGB by the shader for UNORM targets, by the format for *_SRGB ones).
#include "common/common.glsl"
#include "common/lighting.glsl"

layout(set = 0, binding = 0) uniform sampler2DMS scene_color;

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int samples = textureSamples(scene_color);
    vec3 sum = vec3(0.0);
    for (int s = 0; s < samples; s++) {
        sum += clamp(texelFetch(scene_color, pixel, s).rgb, 0.0, 1.0);
    }
    out_color = vec4(encode_output(sum / float(samples)), 1.0);
}
