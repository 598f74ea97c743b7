#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the cull's tiles pass with the beacons' own candidates (beacons.glsl).
#define CLASS_SOURCE
#include "cull/cull.glsl"
#include "beacons.glsl"

uint source_candidates(BladeTile tile, ivec2 cell, uint slot) {
    return beacons_in(tile);
}

#include "cull/tiles_main.glsl"
