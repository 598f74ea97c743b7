// Blades in clumps (`scene::clumps`, `--clumps SIZE_M`): clump centres on a jittered grid of
// CLUMP_SIZE_MM over the world, a blade belonging to the nearest; it faces away from the centre,
// leans the more the farther out it stands, takes most of its clump's hue and its clump's height
// scale (0.7 to 1). The same function as `scene::clumps::Clumps::apply`, on a lattice that repeats
// with the world (the block field's cell modulo PERIOD_CELLS), so the clumps a world period away
// are the same. Without clumps (CLUMP_SIZE_MM 0) it is compiled out.
#ifndef MEADOW_CLUMPS_GLSL
#define MEADOW_CLUMPS_GLSL

#include "common/bezier.glsl"

const float CLUMP_JITTER = 0.7; // scene::clumps::JITTER
const float CLUMP_TINT = 0.75; // scene::clumps::TINT

uint clump_hash(ivec2 k) {
    uint h = uint(k.x) * 0x27d4eb2du ^ uint(k.y) * 0x165667b1u;
    h ^= h >> 15u;
    h *= 0x85ebca6bu;
    return h ^ (h >> 13u);
}

vec2 clump_centre(ivec2 k, float size) {
    uint h = clump_hash(k);
    vec2 jitter = vec2(float((h >> 16u) & 0xffu), float((h >> 24u) & 0xffu)) / 255.0;
    return (vec2(k) + 0.5 + (jitter - 0.5) * CLUMP_JITTER) * size;
}

uint clump_with_byte(uint variation, uint i, float value) {
    uint byte = uint(round(clamp(value, 0.0, 1.0) * 255.0));
    return (variation & ~(0xffu << (8u * i))) | (byte << (8u * i));
}

// `blade` at `lattice` (its world x, z in [0, the world's period)) clumped.
BladeInstance clumped(BladeInstance blade, vec2 lattice) {
    float size = float(CLUMP_SIZE_MM) * 0.001;
    ivec2 k0 = ivec2(floor(lattice / size));
    ivec2 k = k0;
    vec2 c = clump_centre(k0, size);
    for (int dz = -1; dz <= 1; dz++) {
        for (int dx = -1; dx <= 1; dx++) {
            vec2 other = clump_centre(k0 + ivec2(dx, dz), size);
            vec2 a = lattice - other, b = lattice - c;
            if (dot(a, a) < dot(b, b)) {
                k = k0 + ivec2(dx, dz);
                c = other;
            }
        }
    }
    uint h = clump_hash(k);
    vec2 d = lattice - c;
    float spare = unpack_variation(blade.variation, 3);
    blade.facing = atan(d.x, d.y) + (spare - 0.5) * 0.5;
    blade.height *= 0.7 + 0.3 * float((h >> 8u) & 0xffu) / 255.0;
    float own = unpack_variation(blade.variation, 0);
    float hue = own + CLUMP_TINT * (float(h & 0xffu) / 255.0 - own);
    float lean = clamp(0.35 + 0.65 * length(d) / size, 0.0, 1.0);
    blade.variation = clump_with_byte(clump_with_byte(blade.variation, 0u, hue), 2u, lean);
    return blade;
}

#endif
