#version 460
#extension GL_GOOGLE_include_directive : require
// `--msaa`: the resolve of the multisampled scene (`render::msaa`); its variant `single`, the
// single-sampled linear scene of `--fade blend` (no multisampling: one sample). Each pixel's samples hold
// linear radiance; they are clamped to the displayable range one by one (a bright sample must
// not bleed past its share), averaged in linear space, then encoded as the target needs
// (`encode_output`: sRGB by the shader for UNORM targets, by the format for *_SRGB ones).
#include "common/common.glsl"
#include "common/lighting.glsl"

// variant single: SINGLE_SAMPLE
#ifdef SINGLE_SAMPLE
layout(set = 0, binding = 0) uniform sampler2D scene_color;
#else
layout(set = 0, binding = 0) uniform sampler2DMS scene_color;
#endif

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#ifdef SINGLE_SAMPLE
    int samples = 1;
    vec3 sum = clamp(texelFetch(scene_color, pixel, 0).rgb, 0.0, 1.0);
#else
    int samples = textureSamples(scene_color);
    vec3 sum = vec3(0.0);
    for (int s = 0; s < samples; s++) {
        sum += clamp(texelFetch(scene_color, pixel, s).rgb, 0.0, 1.0);
    }
#endif
    out_color = vec4(encode_output(sum / float(samples)), 1.0);
}
