#version 460
#extension GL_GOOGLE_include_directive : require
// Blade levels (with the cull and pose records): each drawn blade's strip levels placed in the
// world and lit once, for blade.vert to widen and project. The vertex shader did this at every
// strip vertex — the blade's record, a block field's placement, the terrain normal under the root,
// Belyaev's lighting and the fog — and llvmpipe runs
// vertex shaders on one thread, where this compute pass runs on all of them, once per level
// instead of once per side. Same functions as the per-vertex path (blade_place.glsl); the fog and
// the Fresnel term's view vector are taken at the centre line, not at each edge.
//
// One invocation per entry of the cull's visible list, dispatched indirectly by the scan's count
// (`POSE_DISPATCH_WORD`), after the model's pose pass; the entry's bucket (its range of the list,
// from the buckets' draws) gives its segment count, and only that many levels are written.
#define LEVELS_WRITER
// Frame values decide loops and branches here: read them as storage (bindings.glsl says why).
#define FRAME_FROM_STORAGE
#include "bindings.glsl"
#include "blade_place.glsl"

layout(set = SET_SCENE, binding = BINDING_DRAWS, std430) readonly buffer Draws { uint draws[]; };

layout(local_size_x = POSE_GROUP) in;

// Segments of the LOD bucket whose draw covers list entry `i` (`cull_lod.y`: 4 bits per bucket).
uint entry_segments(uint i) {
    uint buckets = frame.cull_lod.x;
    for (uint b = 0u; b < buckets; b++) {
        uint first = draws[b * DRAW_WORDS + DRAW_FIRST_INSTANCE] * BLADES_PER_INSTANCE;
        uint end = first + draws[b * DRAW_WORDS + DRAW_INSTANCES] * BLADES_PER_INSTANCE;
        if (i >= first && i < end) {
            return ((frame.cull_lod.y >> (4u * b)) & 15u) + 1u;
        }
    }
    return 0u;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    // Past the list (the last workgroup's tail) or on a bucket's padding: nothing to draw.
    if (i >= draws[POSE_DISPATCH_WORD + 3u]) {
        return;
    }
    uvec2 entry = visible_entry(i);
    uint segments = entry_segments(i);
    if (entry.x == VISIBLE_PADDING || segments == 0u) {
        return;
    }
    uint blade_index;
    BladeInstance blade = visible_instance(entry, blade_index);
    vec2 lod_scale = visible_unpack(entry.y).yz;
    vec3 terrain_normal = blade_terrain_normal(blade);
    uint base = i * (MODEL_SEGMENTS + 1u) * LEVEL_UVEC2S;
    for (uint level = 0u; level <= segments; level++) {
        float t = float(level) / float(segments);
        LevelPose pose = recorded_level(i, blade.height, level, segments);
        PlacedLevel placed = place_level(blade, pose, lod_scale);
        vec4 lit = shade_blade(blade, t, placed.centre, placed.width_dir, placed.tangent, pose.force, segments,
            terrain_normal, lod_scale.y);
        vec3 across = placed.width_dir * placed.width;
        uint at = base + level * LEVEL_UVEC2S;
        levels[at] = floatBitsToUint(placed.centre.xy);
        levels[at + 1u] = uvec2(floatBitsToUint(placed.centre.z), packHalf2x16(across.xz));
        levels[at + 2u] = uvec2(packHalf2x16(lit.rg), packHalf2x16(lit.ba));
    }
}
