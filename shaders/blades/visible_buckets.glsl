// The per-blade passes after the cull (blade_pose.comp, blade_levels.comp) run one dispatch per
// LOD bucket, each with its pipeline specialised for the bucket's segments (SEGMENTS,
// `render::recording::bucket_dispatch`), so a one-segment blade's pose and levels cost what its two
// levels need: no loop or branch on a segment count varying across the SIMD lanes, which llvmpipe
// runs for every lane (a store masked off still costs its loop over the lanes). The scan wrote
// each bucket's draw and dispatch (cull_scan.comp); a bucket's entries are the contiguous range
// its draw's instances cover.
#ifndef MEADOW_VISIBLE_BUCKETS_GLSL
#define MEADOW_VISIBLE_BUCKETS_GLSL
#include "common/bindings.glsl"

// The cull's `Draws` (cull/cull.glsl declares it, the cull owns it), read in the including pass's
// own set (`SET_PASS`) at binding `DRAWS_BINDING` of that pass's numbering (0 unless it says).
#ifndef DRAWS_BINDING
#define DRAWS_BINDING 0
#endif
layout(set = SET_PASS, binding = DRAWS_BINDING, std430) readonly buffer Draws { uint draws[]; };

// The visible-list entry of this invocation: the first entry of the bucket drawn with SEGMENTS
// segments (bucket counts strictly decrease: at most one bucket has them) plus the invocation's
// index; false past the bucket's entries, or when this frame draws no such bucket. The bucket is
// found by selects on the frame's values, not a branch (bindings.glsl says why a branch on
// uniforms alone costs on lavapipe). A pipeline of FLAG_POSE_CLASS covers bucket LOD_BUCKET of a
// further draw class instead (`render::draw_class::DrawClass::posed`: flowers' stems).
bool bucket_entry(out uint i) {
    uint bucket = MAX_LOD_BUCKETS;
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        uint segments = ((frame_values.cull_lod.y >> (4u * b)) & 15u) + 1u;
        uint match = uint(b < frame_values.cull_lod.x) & uint(segments == SEGMENTS);
        bucket = match != 0u ? b : bucket;
    }
    if ((RENDER_FLAGS & FLAG_POSE_CLASS) != 0u) {
        bucket = LOD_BUCKET;
    }
    uint at = min(bucket, MAX_LOD_BUCKETS - 1u) * DRAW_WORDS;
    uint first = draws[at + DRAW_FIRST_INSTANCE] * BLADES_PER_INSTANCE;
    uint count = bucket < MAX_LOD_BUCKETS ? draws[at + DRAW_INSTANCES] * BLADES_PER_INSTANCE : 0u;
    i = first + gl_GlobalInvocationID.x;
    return gl_GlobalInvocationID.x < count;
}

#endif
