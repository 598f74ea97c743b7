#version 460
#extension GL_GOOGLE_include_directive : require
// The depth pyramid over a multisampled depth image (`--msaa`): a pixel's depth is the farthest
// (smallest: reversed Z) of its samples, so the pyramid stays conservative where a pixel is only
// partly covered. The reduction is hiz.glsl's, as in hiz.comp.

layout(set = 0, binding = 0) uniform sampler2DMS depth;

ivec2 depth_size() {
    return textureSize(depth);
}

float depth_texel(ivec2 p) {
    float farthest = 1.0;
    for (int s = 0; s < textureSamples(depth); s++) {
        farthest = min(farthest, texelFetch(depth, p, s).r);
    }
    return farthest;
}

float depth_quad(ivec2 p) {
    return min(min(depth_texel(p), depth_texel(p + ivec2(1, 0))), min(depth_texel(p + ivec2(0, 1)), depth_texel(p + 1)));
}

#include "depth_pyramid/hiz.glsl"

void main() {
    reduce_depth();
}
