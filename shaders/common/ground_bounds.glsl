// Set 0: a heightmap's min/max pyramid (`scene::height_bounds::HeightBounds`, uploaded with the
// ground by `render::ground`): the lowest and highest height of the map under a rectangle of the
// world, for the cull's cell boxes (`field_cell_bounds`, common/field.glsl) under FLAG_GROUND_BOUNDS.
// Without a heightmap the buffer holds an empty header and nothing reads it.
#ifndef MEADOW_GROUND_BOUNDS_GLSL
#define MEADOW_GROUND_BOUNDS_GLSL

// `scene::height_bounds::HeightBounds::words`: a header (levels, the height of white, the map's width and height, its
// extent in x and z, mirrored), a table of BOUNDS_MAX_LEVELS (width, height, first word), then the
// levels, a texel a word: its min sample in the low half, its max in the high half.
layout(SCENE(GroundBounds), std430) readonly buffer GroundBounds { uint bounds_words[]; };
const uint BOUNDS_HEADER = 8u; // scene::height_bounds::HEADER_WORDS
const uint BOUNDS_MAX_LEVELS = 16u; // scene::height_bounds::MAX_LEVELS

// `scene::height_bounds::axis_range`: the texel-coordinate range world `lo`..`hi` covers on an
// axis of `texels` texels over `extent` metres, folded as the map is placed.
vec2 bounds_axis(float lo, float hi, float extent, uint texels, bool mirrored) {
    float scale = float(max(texels, 2u) - 1u);
    float u0 = lo / extent + 0.5;
    float u1 = hi / extent + 0.5;
    vec2 r;
    if (!mirrored) {
        r = clamp(vec2(u0, u1), 0.0, 1.0);
    } else if (u1 - u0 >= 1.0) {
        r = vec2(0.0, 1.0);
    } else {
        float a = mod(u0, 2.0);
        float b = a + (u1 - u0);
        if (b <= 1.0) {
            r = vec2(a, b);
        } else if (a >= 1.0 && b <= 2.0) {
            r = vec2(2.0 - b, 2.0 - a);
        } else if (a < 1.0) {
            r = vec2(min(a, 2.0 - b), 1.0);
        } else {
            r = vec2(0.0, max(2.0 - a, b - 2.0));
        }
    }
    return r * scale;
}

// The lowest and highest height (m) of the map over the world's rectangle `lo`..`hi` (x, z, m,
// relative to the world's origin): the 2 × 2 texels of the level whose texels are as wide as the
// rectangle's range (`scene::height_bounds::HeightBounds::bounds`).
vec2 ground_map_bounds(vec2 lo, vec2 hi) {
    uint levels = bounds_words[0];
    bool mirrored = bounds_words[6] != 0u;
    vec2 x = bounds_axis(lo.x, hi.x, uintBitsToFloat(bounds_words[4]), bounds_words[2], mirrored);
    vec2 z = bounds_axis(lo.y, hi.y, uintBitsToFloat(bounds_words[5]), bounds_words[3], mirrored);
    float span = max(max(x.y - x.x, z.y - z.x), 1.0);
    uint k = min(uint(max(ceil(log2(span)), 1.0)), levels);
    uint entry = BOUNDS_HEADER + 3u * (k - 1u);
    uvec2 size = uvec2(bounds_words[entry], bounds_words[entry + 1u]);
    uint first = bounds_words[entry + 2u];
    float texel = float(1u << k);
    uvec2 i0 = min(uvec2(vec2(x.x, z.x) / texel), size - 1u);
    uvec2 i1 = min(uvec2(vec2(x.y, z.y) / texel), size - 1u);
    uint least = 0xffffu;
    uint most = 0u;
    for (uint j = i0.y; j <= i1.y; j++) {
        for (uint i = i0.x; i <= i1.x; i++) {
            uint word = bounds_words[first + j * size.x + i];
            least = min(least, word & 0xffffu);
            most = max(most, word >> 16u);
        }
    }
    return vec2(float(least), float(most)) / 65535.0 * uintBitsToFloat(bounds_words[1]);
}

#endif
