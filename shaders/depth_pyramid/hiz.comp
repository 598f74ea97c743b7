#version 460
#extension GL_GOOGLE_include_directive : require
// The depth pyramid of this frame's terrain (Hi-Z, as niagara's culling uses it): level 0 has
// PYRAMID_SIDE² texels over the picture in screen space, each the farthest (smallest: reversed Z)
// depth of the pixels it covers; levels 1 and 2 reduce 4×4 texels of the level below. One
// workgroup makes a 16×16 block of level 0 and, in shared memory, the 4×4 and 1×1 blocks of
// levels 1 and 2 above it: one dispatch, no barrier between levels outside the workgroup. The
// cull tests tiles and blades against it (cull.glsl, `occluded`).

layout(set = 0, binding = 0) uniform sampler2D depth;

ivec2 depth_size() {
    return textureSize(depth, 0);
}

float depth_texel(ivec2 p) {
    return texelFetch(depth, p, 0).r;
}

// One gather: the four pixels around the corner they share, p + (1, 1).
float depth_quad(ivec2 p) {
    vec4 q = textureGather(depth, vec2(p + 1) / vec2(depth_size()), 0);
    return min(min(q.x, q.y), min(q.z, q.w));
}

#include "depth_pyramid/hiz.glsl"

void main() {
    reduce_depth();
}
