#version 460
#extension GL_GOOGLE_include_directive : require
// The heightmap's fill of a block field's ground clipmap (`render::ground::heightmap::HeightmapGround`,
// `scene::heightmap`): as relief_fill.comp, the vertices that entered a level's window since the
// last fill (`render::passes::ground_fill`), each with what depends on its world vertex alone:
// the map's height there (bilinear between its texels, mirrored or held past its edges), the next
// level's mesh's height there and the slope of the map's bilinear patch (its rise over 1 m), and
// the cover there (cover_fill.glsl).
// The vertex is named by its place in half-metres on the world's period, so a texel is exact in
// the world: the map is centred on the world's origin and its mirrored period divides the
// world's (`scene::heightmap::TerrainScale::check_period`).
#define GROUND_WRITER
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/camera_grid.glsl"
#define COVER_MAP_BINDING 1
#include "terrain/cover_fill.glsl"

layout(local_size_x = CAMERA_GRID_GROUP) in;

layout(push_constant) uniform Fill {
    CameraGridFill fill;
};

// The map (`render::ground::heightmap::map_words`): `MAP_HEADER` words (width, height, extent x and z and
// the height of white as f32 bits, mirrored), then its texels, two 16-bit texels a word.
layout(set = SET_PASS, binding = 0, std430) readonly buffer GroundMap { uint map_words[]; };
const uint MAP_HEADER = 8u; // render::ground::heightmap::MAP_HEADER_WORDS

uvec2 map_size() {
    return uvec2(map_words[0], map_words[1]);
}

// Texel (x, z) of the map, held inside it, as a height in metres.
float map_texel(ivec2 t) {
    uvec2 size = map_size();
    uvec2 c = uvec2(clamp(t, ivec2(0), ivec2(size) - 1));
    uint i = c.y * size.x + c.x;
    uint word = map_words[MAP_HEADER + i / 2u];
    uint value = (i & 1u) == 0u ? word & 0xffffu : word >> 16u;
    return float(value) / 65535.0 * uintBitsToFloat(map_words[4]);
}

// The map's height at world (x, z) (m, relative to the world's origin) and its slope there: the
// bilinear patch through the texels around it, as `scene::heightmap::Heightmap::height_at`.
float map_at(vec2 world, out vec2 slope) {
    uvec2 size = map_size();
    vec2 per_metre;
    bool mirrored = map_words[5] != 0u;
    vec2 t = vec2(map_coordinate(world.x, uintBitsToFloat(map_words[2]), size.x, mirrored, per_metre.x),
        map_coordinate(world.y, uintBitsToFloat(map_words[3]), size.y, mirrored, per_metre.y));
    vec2 c = floor(t);
    vec2 f = t - c;
    ivec2 i = ivec2(c);
    float h00 = map_texel(i), h10 = map_texel(i + ivec2(1, 0));
    float h01 = map_texel(i + ivec2(0, 1)), h11 = map_texel(i + ivec2(1, 1));
    float bottom = h00 + f.x * (h10 - h00);
    float top = h01 + f.x * (h11 - h01);
    slope = vec2(mix(h10 - h00, h11 - h01, f.y), mix(h01 - h00, h11 - h10, f.x)) * per_metre;
    return bottom + f.y * (top - bottom);
}

void main() {
    uvec3 local = camera_grid_entered(fill, gl_GlobalInvocationID.x);
    uint level = fill.base.w;
    ivec4 window = frame_values.ground_windows[level];
    uint step = uint(2.0 * ground_level_step(level)); // half-metres
    uvec2 at = (uvec2(window.zw) + local.xz * step) % PERIOD_HALF_METRES;
    vec2 world = world_metres(at);
    vec2 unused;
    float h = map_at(world, unused);
    // The slope: the bilinear surface's central difference over a texel either side (at a texel,
    // the mean of the gradients of the patches that meet there, as the stored terrain's central
    // differences; the one-sided gradient of one patch lit the relief's export visibly apart from
    // the relief).
    vec2 texel = vec2(uintBitsToFloat(map_words[2]), uintBitsToFloat(map_words[3])) / vec2(map_size() - 1u);
    vec2 slope = vec2(map_at(world + vec2(texel.x, 0.0), unused) - map_at(world - vec2(texel.x, 0.0), unused),
                     map_at(world + vec2(0.0, texel.y), unused) - map_at(world - vec2(0.0, texel.y), unused))
        / (2.0 * texel);
    // The next level's mesh at an odd vertex: the mean of the two even vertices it halves, as
    // relief_fill.comp takes it.
    float coarse = h;
    uvec2 odd = local.xz & 1u;
    if ((odd.x | odd.y) != 0u) {
        uvec2 across = odd * step;
        vec2 unused;
        uvec2 before = (at + uvec2(PERIOD_HALF_METRES) - across) % PERIOD_HALF_METRES;
        uvec2 after = (at + across) % PERIOD_HALF_METRES;
        coarse = 0.5 * (map_at(world_metres(before), unused) + map_at(world_metres(after), unused));
    }
    uvec3 dims = fill.dims.xyz;
    uint slot = level * dims.x * dims.z + camera_grid_slot(local, fill.base.xyz, dims);
    ground_grid[slot] = vec4(h, coarse, slope);
    ground_cover_grid[slot] = GROUND_COVER != 0u ? ground_cover_at(world, slope) : packUnorm2x16(vec2(1.0));
}
