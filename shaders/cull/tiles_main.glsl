// The tiles pass's body (cull_tiles.comp, and the tiles shader of a set of draw classes with a
// candidate source of its own, `render::draw_class::CandidateSource`): included after
// `source_candidates` when `CLASS_SOURCE` is defined, which says how many candidates of its own a
// visible slot adds after its blades (at most `cull_room.y`; they lie within the slot's box).
#ifndef MEADOW_TILES_MAIN_GLSL
#define MEADOW_TILES_MAIN_GLSL

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
        uint blades = recorded ? tile_candidates(f, tile, tile_normal(tile), cover, tile_visible) : 0u;
        uint candidates = blades;
#ifdef CLASS_SOURCE
        // The class set's own candidates, after the blades, in a slot the tile tests keep.
        candidates += tile_visible ? min(source_candidates(tile, cell, slot), frame.cull_room.y) : 0u;
#endif
        alloc_words[slots + slot] = candidates;
        alloc_words[3u * slots + slot] = blades;
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
        // The verdicts' room: the slots nearer than this one took theirs before it.
        bool fits = first + candidates <= frame.cull_room.x;
        alloc_words[slot] = fits ? first : NO_ROOM;
        first += candidates;
    }
}

#endif
