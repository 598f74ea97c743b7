// The colliders binned over the ground (`render::animation::collider_bins`): a blade tests only
// the colliders whose ground ellipse may hold its root. The grid follows the emitters in set 0's
// `Emitters` (animation/frame_forces.glsl): a header (the first corner x, z relative to O, the bin
// edge, bins per side; w 0 when no collider), then per bin its 128-bit mask as eight 16-bit
// integers (two elements).
#ifndef MEADOW_COLLIDER_BINS_GLSL
#define MEADOW_COLLIDER_BINS_GLSL

const uint COLLIDER_BINS = EMITTER_ELEMENTS; // render::animation::collider_bins::COLLIDER_BINS
const uint COLLIDER_BIN_DIMS = 32u;           // render::animation::collider_bins::BIN_DIMS

// The colliders whose ground ellipse may hold `root` (x, z relative to O): bit i of word i / 32
// for collider i.
uvec4 colliders_near(vec2 root) {
    vec4 head = emitters[COLLIDER_BINS];
    if (head.w == 0.0) {
        return uvec4(0u);
    }
    vec2 b = floor((root - head.xy) / head.z);
    if (any(lessThan(b, vec2(0.0))) || any(greaterThanEqual(b, vec2(float(COLLIDER_BIN_DIMS))))) {
        return uvec4(0u);
    }
    uint at = COLLIDER_BINS + 1u + 2u * (uint(b.y) * COLLIDER_BIN_DIMS + uint(b.x));
    uvec4 lo = uvec4(emitters[at]);
    uvec4 hi = uvec4(emitters[at + 1u]);
    return uvec4(lo.x | (lo.y << 16u), lo.z | (lo.w << 16u), hi.x | (hi.y << 16u), hi.z | (hi.w << 16u));
}

// The lowest collider of `near`, taken out of it.
uint next_collider(inout uvec4 near) {
    uint w = near.x != 0u ? 0u : (near.y != 0u ? 1u : (near.z != 0u ? 2u : 3u));
    uint word = near[w];
    near[w] = word & (word - 1u);
    return 32u * w + uint(findLSB(word));
}

#endif
