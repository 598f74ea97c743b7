#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the cull's count pass for the blade class and a class of markers defined
// in tests/ (`render::draw_class`). A marker claims every seventh stored blade (its index mod 7 is
// 3) that the blade tests keep, in the markers' one bucket (the class's first); the others stay
// the blade class's, in their LOD buckets.
#include "cull/cull.glsl"

int class_bucket(Frustum f, BladeTile tile, uint slot, uint rank, BladeInstance blade, vec3 normal, out uint failed, out vec2 scale) {
    int bucket = blade_bucket(f, blade, rank, tile.count, normal, failed, scale);
    bool claimed = visible_blade(tile, slot, rank) % 7u == 3u;
    return bucket >= 0 && claimed ? int(class_first_bucket(1u)) : bucket;
}

#include "cull/count_main.glsl"
