// The colliders binned over the ground (`render::animation::collider_bins`): a blade tests only
// the colliders whose ground ellipse may hold its root. The grid follows the emitters in set 0's
// `Emitters` (animation/frame_forces.glsl): a header (the first corner x, z relative to O, the bin
// edge, bins per side; w 0 when no collider), then per bin its 64-bit mask as four 16-bit integers.
#ifndef MEADOW_COLLIDER_BINS_GLSL
#define MEADOW_COLLIDER_BINS_GLSL

const uint COLLIDER_BINS = 2u * MAX_EMITTERS; // render::animation::collider_bins::COLLIDER_BINS
const uint COLLIDER_BIN_DIMS = 32u;           // render::animation::collider_bins::BIN_DIMS

// The colliders whose ground ellipse may hold `root` (x, z relative to O): bit i (of x, then of
// y for 32 and up) for collider i.
uvec2 colliders_near(vec2 root) {
    vec4 head = emitters[COLLIDER_BINS];
    if (head.w == 0.0) {
        return uvec2(0u);
    }
    vec2 b = floor((root - head.xy) / head.z);
    if (any(lessThan(b, vec2(0.0))) || any(greaterThanEqual(b, vec2(float(COLLIDER_BIN_DIMS))))) {
        return uvec2(0u);
    }
    uvec4 h = uvec4(emitters[COLLIDER_BINS + 1u + uint(b.y) * COLLIDER_BIN_DIMS + uint(b.x)]);
    return uvec2(h.x | (h.y << 16u), h.z | (h.w << 16u));
}

// The lowest collider of `near`, taken out of it.
uint next_collider(inout uvec2 near) {
    if (near.x != 0u) {
        uint i = uint(findLSB(near.x));
        near.x &= near.x - 1u;
        return i;
    }
    uint i = uint(findLSB(near.y));
    near.y &= near.y - 1u;
    return 32u + i;
}

#endif
