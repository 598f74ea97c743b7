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
// One dispatch per LOD bucket (visible_buckets.glsl), one invocation per entry of the bucket's
// range of the cull's visible list, dispatched indirectly by the scan's count, after the model's
// pose pass; the bucket's segment count (SEGMENTS) is how many levels are written.
#define LEVELS_WRITER
// Frame values decide loops and branches here: read them as storage (bindings.glsl says why).
#define FRAME_FROM_STORAGE
#include "common/bindings.glsl"
#include "blades/blade_place.glsl"
#include "blades/visible_buckets.glsl"

layout(local_size_x = POSE_GROUP) in;

void main() {
    uint i;
    // Past the bucket (the last workgroup's tail) or on its padding: nothing to draw.
    if (!bucket_entry(i)) {
        return;
    }
    uvec2 entry = visible_entry(i);
    if (entry.x == VISIBLE_PADDING) {
        return;
    }
    uint segments = SEGMENTS;
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
