#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the cull's count pass for the blade class and the beacons: the blades go
// to their LOD buckets as without the class, the beacons (the class's own candidates,
// beacons.glsl) that are kept to the beacons' one bucket.
#define CLASS_SOURCE
#include "cull/cull.glsl"
#include "beacons.glsl"

int class_bucket(Frustum f, BladeTile tile, uint slot, uint rank, BladeInstance blade, vec3 normal, out uint failed, out vec2 scale) {
    return blade_bucket(f, blade, rank, tile.count, normal, failed, scale);
}

int source_bucket(Frustum f, BladeTile tile, ivec2 cell, uint slot, uint rank, vec3 normal, out vec2 scale, out float root_y) {
    scale = vec2(1.0);
    root_y = beacon_y(tile);
    return beacon_kept(tile, rank) ? int(class_first_bucket(1u)) : -1;
}

#include "cull/count_main.glsl"
