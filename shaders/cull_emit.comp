#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 3 of 3: one workgroup per ring slot writes each blade the count pass drew (its
// verdict in `cull_results`) to the visible list at bucket base + slot offset + its rank among
// the slot's blades of its bucket. Invocation i takes the i-th contiguous run of the slot's
// candidates: it counts its run per bucket, one prefix sum over the runs gives each run its
// start, and it writes its run in order. The list is the same on every run and thread count:
// buckets, then slots near to far, then stored order (the order brute force draws a tile in).
#define CULL_WRITER
#include "cull.glsl"

layout(local_size_x = CULL_GROUP) in;

shared uint prefix[MAX_LOD_BUCKETS][CULL_GROUP];

// The count pass's verdict on blade `rank` as (bucket, the visible entry's second word): read
// back for a stored field, the same tests run again for a block field (whose blades share their
// indices across cells), whose root height the entry carries.
uvec2 verdict(Frustum f, BladeTile tile, ivec2 cell, uint rank, vec3 normal) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) == 0u) {
        uvec2 stored = cull_results[tile.first + rank];
        return uvec2(stored.x, visible_scale(0.0, unpackHalf2x16(stored.y)));
    }
    uint failed;
    vec2 scale;
    BladeInstance blade = tile_blade(tile, cell, rank);
    int bucket = blade_bucket(f, blade, rank, tile.count, normal, failed, scale);
    return uvec2(bucket >= 0 ? uint(bucket) : NOT_DRAWN, visible_scale(blade.position.y, scale));
}

void main() {
    uint slot = gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationID.x;
    BladeTile tile;
    ivec2 cell;
    if (!slot_record(slot, tile, cell)) {
        return;
    }
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        cache_cell_heights(cell);
    }
    Frustum f = culling_frustum();
    bool tile_visible;
    uint candidates = tile_candidates(f, tile, tile_visible);
    vec3 normal = tile_normal(tile);
    if (candidates == 0u) {
        return;
    }
    uint run = (candidates + CULL_GROUP - 1u) / CULL_GROUP;
    uint begin = min(lane * run, candidates);
    uint end = min(begin + run, candidates);
    uint own[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        own[b] = 0u;
    }
    for (uint rank = begin; rank < end; rank++) {
        uint bucket = verdict(f, tile, cell, rank, normal).x;
        // Constant indices only: llvmpipe keeps the counters in registers.
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            own[b] += bucket == b ? 1u : 0u;
        }
    }
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        prefix[b][lane] = own[b];
    }
    barrier();
    // Exclusive prefix over the runs, by one invocation: two barriers instead of a parallel scan's
    // twelve, which on llvmpipe cost more than the 512 additions.
    if (lane == 0u) {
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            uint sum = 0u;
            for (uint i = 0u; i < CULL_GROUP; i++) {
                uint count = prefix[b][i];
                prefix[b][i] = sum;
                sum += count;
            }
        }
    }
    barrier();
    uint at[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        // Bucket base (the draw's firstInstance) + the slot's offset + the runs before this one.
        at[b] = draws[4u * b + 3u] + slot_counts[slot * SLOT_WORDS + b] + prefix[b][lane];
    }
    for (uint rank = begin; rank < end; rank++) {
        uvec2 result = verdict(f, tile, cell, rank, normal);
        uint position = 0u;
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            position = result.x == b ? at[b] : position;
            at[b] += result.x == b ? 1u : 0u;
        }
        if (result.x != NOT_DRAWN && position < frame.cull_lod.w) {
            visible[position] = uvec2(visible_blade(tile, slot, rank), result.y);
        }
    }
}
