// The count pass's body (cull_count.comp, and the count shaders of a set of draw classes,
// `render::draw_class::DrawClasses`, its `count_shader`): included after `class_bucket`, the classes'
// selection, which sorts each candidate blade into a bucket of its class (or none), and with
// `CLASS_SOURCE` defined after `source_bucket`, which sorts each candidate of the set's own source
// (`render::draw_class::CandidateSource`) into a bucket (or none), with its fade and widening and
// its root's height for the visible entry.
#ifndef MEADOW_COUNT_MAIN_GLSL
#define MEADOW_COUNT_MAIN_GLSL

layout(local_size_x_id = SPEC(CULL_GROUP)) in;

shared uint counts[SLOT_WORDS];

void main() {
    read_cull_settings();
    uint slot = listed_slot(spread(gl_WorkGroupID.x, count_dispatch.w));
    uint lane = gl_LocalInvocationID.x;
    for (uint w = lane; w < SLOT_WORDS; w += CULL_GROUP) {
        counts[w] = 0u;
    }
    barrier();
    BladeTile tile;
    ivec2 cell;
    if (slot_record(slot, tile, cell)) {
        Frustum f = culling_frustum();
        vec3 normal = tile_normal(tile);
        // A listed slot passed the tile tests with candidates (the tiles pass): its blades'
        // ranks first, then its own source's; room for their verdicts from the tiles pass's
        // prefix sum.
        uint candidates = slot_candidates(slot);
        uint blades = slot_blade_candidates(slot);
        uint base = verdict_base(slot);
        candidates = base == NO_ROOM ? 0u : candidates;
        blades = min(blades, candidates);
        if (lane == 0u) {
            counts[STAT_CONSIDERED] = tile.count;
            counts[STAT_TILES_TOTAL] = 1u;
            counts[STAT_TILES] = tile.count;
            counts[STAT_TILES_VISIBLE] = 1u;
        }
        uint passed[STAT_OCCLUSION - STAT_DENSITY + 1u] = uint[](0u, 0u, 0u, 0u);
        uint drawn[MAX_LOD_BUCKETS] = uint[](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
        for (uint rank = lane; rank < blades; rank += CULL_GROUP) {
            uint failed;
            vec2 scale;
            BladeInstance blade = tile_blade(tile, cell, rank);
            int bucket = class_bucket(f, tile, slot, rank, blade, normal, failed, scale);
            for (uint s = 0u; s <= STAT_OCCLUSION - STAT_DENSITY; s++) {
                passed[s] += (failed == 0u || STAT_DENSITY + s < failed) ? 1u : 0u;
            }
            // Constant indices only: llvmpipe keeps the counters in registers.
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                drawn[b] += bucket == int(b) ? 1u : 0u;
            }
            uint verdict = bucket >= 0 ? uint(bucket) : NOT_DRAWN;
            cull_results[verdict_index(base, rank)] = uvec2(verdict, visible_scale(blade.position.y, scale));
        }
#ifdef CLASS_SOURCE
        // The own source's candidates (`source_bucket`): in the buckets, not in the blade
        // tests' counts.
        for (uint rank = lane; rank < candidates - blades; rank += CULL_GROUP) {
            vec2 scale = vec2(1.0);
            float root_y = 0.0;
            int bucket = source_bucket(f, tile, cell, slot, rank, normal, scale, root_y);
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                drawn[b] += bucket == int(b) ? 1u : 0u;
            }
            uint verdict = bucket >= 0 ? uint(bucket) : NOT_DRAWN;
            cull_results[verdict_index(base, blades + rank)] = uvec2(verdict, visible_scale(root_y, scale));
        }
#endif
        for (uint s = 0u; s <= STAT_OCCLUSION - STAT_DENSITY; s++) {
            atomicAdd(counts[STAT_DENSITY + s], passed[s]);
        }
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            atomicAdd(counts[b], drawn[b]);
        }
    }
    barrier();
    for (uint w = lane; w < SLOT_WORDS; w += CULL_GROUP) {
        slot_counts[slot * SLOT_WORDS + w] = counts[w];
    }
}

#endif
