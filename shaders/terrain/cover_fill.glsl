// The ground's cover as the ground's fills write it (`scene::cover`, relief_fill.comp and
// heightmap_fill.comp): the covering map's density at the vertex times the slope limit's factor.
// The slope limit's factor over ground of slope `slope` (rise over run) is 1 below the soft
// edge, 0 above it, smoothstep across it (`scene::cover::slope_density`). The
// limit and the edge's width come from the frame (`ground.y`, `ground.w`, radians; without a
// limit, 10 radians: no slope reaches it), read in arithmetic alone: lavapipe compiles a variant
// of a compute pipeline per value of a uniform that decides a branch (profile.glsl's rule).
#ifndef MEADOW_COVER_FILL_GLSL
#define MEADOW_COVER_FILL_GLSL

#include "terrain/map_coordinate.glsl"

// The covering map (`render::ground::cover::cover_map_words`) in the fill's own set: a header of
// `COVER_HEADER` words (width, height, extent x and z as f32 bits, mirrored, the flower plane's
// first word), then its grass densities, four bytes a word, then its flower densities likewise.
// Without a map, 1 × 1 of 255. The including fill sets its binding.
#ifndef COVER_MAP_BINDING
#define COVER_MAP_BINDING 0
#endif
layout(set = SET_PASS, binding = COVER_MAP_BINDING, std430) readonly buffer CoverMap { uint cover_words[]; };
const uint COVER_HEADER = 8u; // render::ground::cover::COVER_MAP_HEADER_WORDS

float slope_cover(vec2 slope) {
    float limit = uintBitsToFloat(frame_values.ground.y);
    float soft = uintBitsToFloat(frame_values.ground.w);
    float angle = atan(length(slope));
    float t = clamp((angle - (limit - 0.5 * soft)) / max(soft, 1e-6), 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

// Texel (x, z) of the covering map, held inside it, as the grass's (x) and flowers' (y)
// densities in [0, 1].
vec2 cover_texel(ivec2 t) {
    uvec2 size = uvec2(cover_words[0], cover_words[1]);
    uvec2 c = uvec2(clamp(t, ivec2(0), ivec2(size) - 1));
    uint i = c.y * size.x + c.x;
    uint shift = 8u * (i & 3u);
    uint grass = cover_words[COVER_HEADER + i / 4u];
    uint flowers = cover_words[cover_words[5] + i / 4u];
    return vec2(float((grass >> shift) & 0xffu), float((flowers >> shift) & 0xffu)) / 255.0;
}

// The covering map's densities at world (x, z) (m, relative to the world's origin), the grass's
// (x) and the flowers' (y): bilinear between its texels (`scene::cover::CoverMap::density_at`,
// `flower_density_at`).
vec2 cover_map_at(vec2 world) {
    uvec2 size = uvec2(cover_words[0], cover_words[1]);
    bool mirrored = cover_words[4] != 0u;
    vec2 unused;
    vec2 t = vec2(map_coordinate(world.x, uintBitsToFloat(cover_words[2]), size.x, mirrored, unused.x),
        map_coordinate(world.y, uintBitsToFloat(cover_words[3]), size.y, mirrored, unused.y));
    vec2 c = floor(t);
    vec2 f = t - c;
    ivec2 i = ivec2(c);
    vec2 bottom = mix(cover_texel(i), cover_texel(i + ivec2(1, 0)), f.x);
    vec2 top = mix(cover_texel(i + ivec2(0, 1)), cover_texel(i + ivec2(1, 1)), f.x);
    return mix(bottom, top, f.y);
}

// The cover at world (x, z) over ground of slope `slope`, packed as `GroundCover` holds it: the
// map's densities times the slope's.
uint ground_cover_at(vec2 world, vec2 slope) {
    return packUnorm2x16(cover_map_at(world) * slope_cover(slope));
}

#endif
