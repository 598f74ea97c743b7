// The depth pyramid's reduction (hiz.comp, hiz_ms.comp): the including shader declares the depth
// image and defines `ivec2 depth_size()`, `float depth_texel(ivec2)`, the farthest depth of a
// pixel, and `float depth_quad(ivec2 p)`, the farthest of the 2×2 pixels from p.
#ifndef MEADOW_HIZ_GLSL
#define MEADOW_HIZ_GLSL
#include "common/shared.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 1, std430) writeonly buffer Pyramid { float pyramid[]; };

shared float level0[16][16];
shared float level1[4][4];

void reduce_depth() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uvec2 local = gl_LocalInvocationID.xy;
    ivec2 size = depth_size();
    // The pixels this texel covers: at least one.
    ivec2 lo = ivec2(texel * uvec2(size) / PYRAMID_SIDE);
    ivec2 hi = max(ivec2((texel + 1u) * uvec2(size) / PYRAMID_SIDE), lo + 1);
    float farthest = 1.0;
    if (all(greaterThanEqual(hi - lo, ivec2(2)))) {
        // By 2×2 quads (a gather reads four pixels at once), the last of each row and column
        // moved back to end at `hi`: they overlap, and the minimum does not mind. At 1280×720 a
        // texel covers 5×2 or 5×3 pixels: 6 gathers instead of up to 15 fetches.
        for (int y = lo.y; y < hi.y; y += 2) {
            for (int x = lo.x; x < hi.x; x += 2) {
                farthest = min(farthest, depth_quad(min(ivec2(x, y), hi - 2)));
            }
        }
    } else {
        for (int y = lo.y; y < hi.y; y++) {
            for (int x = lo.x; x < hi.x; x++) {
                farthest = min(farthest, depth_texel(ivec2(x, y)));
            }
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

#endif
