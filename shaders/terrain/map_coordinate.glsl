// Placing a map on the world (`scene::heightmap::map_coordinate`): the heightmap's fill and the
// covering map's (heightmap_fill.comp, cover_fill.glsl) centre a map on the world's origin.
#ifndef MEADOW_MAP_COORDINATE_GLSL
#define MEADOW_MAP_COORDINATE_GLSL

// World (x or z, m, relative to the world's origin) on a map of `texels` along `extent` metres,
// in texels (its lattice spans [0, texels − 1]), mirrored past its edges or held at them; and
// d(texel)/d(world) there (negative on a mirrored copy, 0 where held).
float map_coordinate(float world, float extent, uint texels, bool mirrored, out float per_metre) {
    float u = world / extent + 0.5;
    float scale = float(max(texels, 1u) - 1u);
    per_metre = scale / extent;
    if (mirrored) {
        u = mod(u, 2.0);
        if (u > 1.0) {
            u = 2.0 - u;
            per_metre = -per_metre;
        }
    } else if (u < 0.0 || u > 1.0) {
        u = clamp(u, 0.0, 1.0);
        per_metre = 0.0;
    }
    return u * scale;
}

// World vertex `at` (half-metres on the world's period) in metres relative to the world's
// origin, the period's second half being the negative side.
vec2 world_metres(uvec2 at) {
    vec2 m = vec2(at) * 0.5;
    float half_period = float(PERIOD_HALF_METRES) * 0.25;
    return mix(m, m - 2.0 * half_period, greaterThanEqual(m, vec2(half_period)));
}

#endif
