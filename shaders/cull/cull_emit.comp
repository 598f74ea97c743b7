#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 4 of 4: one workgroup per ring slot that draws (the scan lists them) writes each
// blade the count pass drew (its verdict in `cull_results`, the visible entry's second word
// included) to the visible list at bucket base + slot offset + its rank among the slot's blades
// of its bucket. Invocation i takes the i-th contiguous run of the slot's candidates: it counts
// its run per bucket, one prefix sum over the runs gives each run its start, and it writes its
// run in order. The list is the same on every run and thread count: buckets, then slots near to
// far, then stored order (the order brute force draws a tile in), a slot's own source's
// candidates after its blades. When the scan's capacity scale is under one, each bucket's
// sequence is thinned evenly by it (`thin_kept`, cull.glsl).
#define CULL_WRITER
#include "cull/cull.glsl"

layout(local_size_x_id = SPEC(CULL_GROUP)) in;

// The count pass's verdicts (`cull_results`), in the lavapipe profile as texels: llvmpipe gathers
// a texel fetch across the SIMD lanes, where it loads storage one lane at a time.
#ifdef TEXEL_TWINS
// Binding 6 of the cull's set (cull/cull.glsl numbers 0-5).
layout(set = SET_PASS, binding = 6) uniform usamplerBuffer verdict_texels;
uvec2 verdict(uint index) {
    return texelFetch(verdict_texels, int(index)).xy;
}
#else
uvec2 verdict(uint index) {
    return cull_results[index];
}
#endif

shared uint prefix[MAX_LOD_BUCKETS][CULL_GROUP];


void main() {
    read_cull_settings();
    // One workgroup per slot that draws (the scan's list, dispatched indirectly), spread over
    // llvmpipe's threads as in the count pass.
    uint slot = draws[EMIT_SLOTS_WORD + spread(gl_WorkGroupID.x, draws[EMIT_DISPATCH_WORD])];
    uint lane = gl_LocalInvocationID.x;
    BladeTile tile;
    ivec2 cell;
    if (!slot_record(slot, tile, cell)) {
        return;
    }
    // The tile tests' result, from the tiles pass: the blades' ranks, then the own source's.
    uint candidates = slot_candidates(slot);
    if (candidates == 0u) {
        return;
    }
    uint base = verdict_base(slot);
    if (base == NO_ROOM) {
        return;
    }
    uint blades = slot_blade_candidates(slot);
    uint run = (candidates + CULL_GROUP - 1u) / CULL_GROUP;
    uint begin = min(lane * run, candidates);
    uint end = min(begin + run, candidates);
    uint own[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        own[b] = 0u;
    }
    for (uint rank = begin; rank < end; rank++) {
        uint bucket = verdict(verdict_index(base, rank)).x;
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
    uint scale = draws[THIN_WORD];
    uint first[MAX_LOD_BUCKETS];
    uint at[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        // Bucket base (the draw's firstInstance, instances of BLADES_PER_INSTANCE entries), and
        // the entry's index in its bucket's sequence: the slot's offset + the runs before this one.
        first[b] = draws[DRAW_WORDS * b + DRAW_FIRST_INSTANCE] * BLADES_PER_INSTANCE;
        at[b] = slot_counts[slot * SLOT_WORDS + b] + prefix[b][lane];
    }
    for (uint rank = begin; rank < end; rank++) {
        uvec2 result = verdict(verdict_index(base, rank));
        uint bucket_first = 0u;
        uint k = 0u;
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            bucket_first = result.x == b ? first[b] : bucket_first;
            k = result.x == b ? at[b] : k;
            at[b] += result.x == b ? 1u : 0u;
        }
        uint position = bucket_first + thin_position(k, scale);
        if (result.x != NOT_DRAWN && thin_kept(k, scale) && position < cull_settings.w) {
            uint entry = rank < blades ? visible_blade(tile, slot, rank) : visible_source(slot, rank - blades);
            visible[position] = uvec2(entry, result.y);
        }
    }
}
