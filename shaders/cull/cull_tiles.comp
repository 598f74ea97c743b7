#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 1 of 4: one workgroup runs the tile tests of every ring slot (cull.glsl,
// `tile_candidates`), a SIMD lane per slot. A slot without candidates gets its `SLOT_WORDS` words
// here (the count pass skips it). Every slot's candidates go to `cull_alloc` (the count and
// emit passes read them: the tile tests run once per slot and frame), and the slots with
// candidates are listed in slot order (near to far) with the count pass's indirect dispatch:
// an empty workgroup costs llvmpipe about 0.9 µs, 5.6 ms over the 6 241 slots of an unbounded
// field at 150 m, most of them off screen. A block field's slots take their verdicts' room by a
// prefix sum of their candidates in slot order: no atomics, no counter to clear.
// Invocation i walks the i-th contiguous run of slots, one invocation scans the run sums, then
// each invocation writes its run's list entries and room.
#include "cull/cull.glsl"

const uint RUNS = 256u;
layout(local_size_x = RUNS) in;

shared uint run_listed[RUNS];
shared uint run_candidates[RUNS];

// The words the count pass would write for a slot without candidates (cull_count.comp). A tile
// can pass the tile tests and still have none: facing away, the density bound keeps nothing.
void write_empty_slot(uint slot, bool recorded, BladeTile tile, bool tile_visible) {
    for (uint w = 0u; w < SLOT_WORDS; w++) {
        slot_counts[slot * SLOT_WORDS + w] = 0u;
    }
    if (recorded) {
        slot_counts[slot * SLOT_WORDS + STAT_CONSIDERED] = tile.count;
        slot_counts[slot * SLOT_WORDS + STAT_TILES_TOTAL] = 1u;
        slot_counts[slot * SLOT_WORDS + STAT_TILES] = tile_visible ? tile.count : 0u;
        slot_counts[slot * SLOT_WORDS + STAT_TILES_VISIBLE] = tile_visible ? 1u : 0u;
    }
}

void main() {
    read_cull_settings();
    uint lane = gl_LocalInvocationID.x;
    uint slots = frame.cull_tiles.y;
    uint per = (slots + RUNS - 1u) / RUNS;
    uint begin = min(lane * per, slots);
    uint end = min(begin + per, slots);
    Frustum f = culling_frustum();
    uint listed = 0u;
    uint candidates_sum = 0u;
    for (uint slot = begin; slot < end; slot++) {
        BladeTile tile;
        ivec2 cell;
        bool recorded = slot_record(slot, tile, cell);
        float cover = 1.0;
        if (recorded) {
            slot_bounds(cell, tile, cover);
        }
        bool tile_visible = false;
        uint candidates = recorded ? tile_candidates(f, tile, tile_normal(tile), cover, tile_visible) : 0u;
        alloc_words[slots + slot] = candidates;
        if (candidates == 0u) {
            write_empty_slot(slot, recorded, tile, tile_visible);
        }
        listed += candidates > 0u ? 1u : 0u;
        candidates_sum += candidates;
    }
    run_listed[lane] = listed;
    run_candidates[lane] = candidates_sum;
    barrier();
    if (lane == 0u) {
        uint total = 0u;
        uint room = 0u;
        for (uint r = 0u; r < RUNS; r++) {
            uint l = run_listed[r];
            uint c = run_candidates[r];
            run_listed[r] = total;
            run_candidates[r] = room;
            total += l;
            room += c;
        }
        count_dispatch = uvec4(total, 1u, 1u, total);
    }
    barrier();
    uint at = run_listed[lane];
    uint first = run_candidates[lane];
    for (uint slot = begin; slot < end; slot++) {
        uint candidates = alloc_words[slots + slot];
        if (candidates > 0u) {
            alloc_words[2u * slots + at] = slot;
            at++;
        }
        // A block field's verdicts: the slots nearer than this one took the room before it.
        bool fits = (RENDER_FLAGS & FLAG_BLOCKS) == 0u || first + candidates <= frame.cull_tiles.x;
        alloc_words[slot] = fits ? first : NO_ROOM;
        first += candidates;
    }
}
