#version 460
#extension GL_GOOGLE_include_directive : require
// The depth pyramid of this frame's terrain (Hi-Z, as niagara's culling uses it): level 0 has
// PYRAMID_SIDE² texels over the picture in screen space, each the farthest (smallest: reversed Z)
// depth of the pixels it covers; levels 1 and 2 reduce 4×4 texels of the level below. One
// workgroup makes a 16×16 block of level 0 and, in shared memory, the 4×4 and 1×1 blocks of
// levels 1 and 2 above it: one dispatch, no barrier between levels outside the workgroup. The
// cull tests tiles and blades against it (cull.glsl, `occluded`).
#include "shared.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 0) uniform sampler2D depth;
layout(set = 0, binding = 1, std430) writeonly buffer Pyramid { float pyramid[]; };

shared float level0[16][16];
shared float level1[4][4];

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uvec2 local = gl_LocalInvocationID.xy;
    ivec2 size = textureSize(depth, 0);
    // The pixels this texel covers: at least one.
    ivec2 lo = ivec2(texel * uvec2(size) / PYRAMID_SIDE);
    ivec2 hi = max(ivec2((texel + 1u) * uvec2(size) / PYRAMID_SIDE), lo + 1);
    float farthest = 1.0;
    for (int y = lo.y; y < hi.y; y++) {
        for (int x = lo.x; x < hi.x; x++) {
            farthest = min(farthest, texelFetch(depth, ivec2(x, y), 0).r);
        }
    }
    pyramid[texel.y * PYRAMID_SIDE + texel.x] = farthest;
    level0[local.y][local.x] = farthest;
    barrier();
    if (all(lessThan(local, uvec2(4u)))) {
        float m = 1.0;
        for (uint y = 0u; y < 4u; y++) {
            for (uint x = 0u; x < 4u; x++) {
                m = min(m, level0[local.y * 4u + y][local.x * 4u + x]);
            }
        }
        level1[local.y][local.x] = m;
        uvec2 at = gl_WorkGroupID.xy * 4u + local;
        pyramid[PYRAMID_SIDE * PYRAMID_SIDE + at.y * (PYRAMID_SIDE / 4u) + at.x] = m;
    }
    barrier();
    if (local == uvec2(0u)) {
        float m = 1.0;
        for (uint y = 0u; y < 4u; y++) {
            for (uint x = 0u; x < 4u; x++) {
                m = min(m, level1[y][x]);
            }
        }
        uint base = PYRAMID_SIDE * PYRAMID_SIDE + (PYRAMID_SIDE / 4u) * (PYRAMID_SIDE / 4u);
        pyramid[base + gl_WorkGroupID.y * (PYRAMID_SIDE / 16u) + gl_WorkGroupID.x] = m;
    }
}
