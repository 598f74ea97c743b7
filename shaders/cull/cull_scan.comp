#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 3 of 4: one workgroup turns the per-slot bucket counts into offsets (an exclusive
// prefix sum over the slots, in slot order: near to far, or far to near for the buckets of a
// class drawn so, `bucket_far_to_near`), writes one indirect draw per bucket of every draw class
// (its instances are bucket b's blades, from firstInstance = the blades of the buckets before it)
// and the blade-pose and levels passes' indirect dispatch over each bucket, lists the slots that
// draw (in slot order) with the emit pass's indirect dispatch over them, and sums the frame's
// counts into the host-visible `cull_stats` (read after the frame's fence). When the blades the
// blade tests keep do not fit the visible list, it writes the capacity scale the emit pass thins
// every bucket by (`thin_position`, cull.glsl), so that they fit in the same frame.
// Invocation i sums the i-th contiguous run of slots, one invocation scans the run sums, then
// each invocation writes its run's offsets: three barriers (a parallel scan needs two per step,
// and llvmpipe's barriers cost more than the additions they save).
#define CULL_WRITER
#include "cull/cull.glsl"
#include "cull/tile_rows.glsl"

// The blade class's per-tile rows (cull/tile_rows.glsl), binding 7 of the cull's set (cull.glsl
// numbers 0-5, cull_emit.comp 6); written only when TILE_ROWS_CAPACITY > 0.
layout(set = SET_PASS, binding = 7, std430) writeonly buffer TileRows { uint tile_rows[]; };

const uint SCAN = 256u;
layout(local_size_x = SCAN) in;

shared uint run_start[MAX_LOD_BUCKETS][SCAN];
shared uint totals[SLOT_WORDS];
// Per run: the slots of the run that draw, then (after the scan) where the run's go in the list.
shared uint run_slots[SCAN];
shared uint drawing_slots;
// The capacity scale (`THIN_WORD`), the blades the blade tests kept, and the candidates
// without room for their verdicts (`NO_ROOM`).
shared uint thin_scale;
shared uint wanted;
shared uint lost_to_room;
// Each bucket's place in the visible list (its first entry and its entries, thinned), its
// entries before thinning, and its instance's draw (`bucket_draw`); with per-tile rows, per run
// the tiles that draw each bucket (then, after the scan, where the run's rows go), and each
// bucket's rows.
shared uint bucket_first[MAX_LOD_BUCKETS];
shared uint bucket_count[MAX_LOD_BUCKETS];
shared uint bucket_wanted[MAX_LOD_BUCKETS];
shared uvec2 bucket_draws[MAX_LOD_BUCKETS];
shared uint run_tiles[MAX_LOD_BUCKETS][SCAN];
shared uint bucket_tiles[MAX_LOD_BUCKETS];

// floor(2^32 room / total) for room < total < 2^31: the 0.32 fixed-point quotient, a bit at a time
// (the remainder stays under total, so doubling it fits 32 bits).
uint fixed_ratio(uint room, uint total) {
    uint q = 0u;
    uint r = room;
    for (uint i = 0u; i < 32u; i++) {
        r <<= 1u;
        q <<= 1u;
        if (r >= total) {
            r -= total;
            q |= 1u;
        }
    }
    return q;
}

// Lane 0, once the totals are known: SCALE_ONE when every bucket's blades, each bucket padded to
// whole instances, fit the visible list's `cull_lod.w` entries; else room / kept, room being the
// list less the most padding the buckets can need, so that the thinned buckets fit padded.
uint capacity_scale(uint kept) {
    const uint batch = BLADES_PER_INSTANCE;
    uint padded = 0u;
    for (uint b = 0u; b < draw_buckets(); b++) {
        padded += (totals[b] + batch - 1u) / batch * batch;
    }
    if (padded <= frame.cull_lod.w) {
        return SCALE_ONE;
    }
    uint slack = draw_buckets() * (batch - 1u);
    return fixed_ratio(frame.cull_lod.w - min(slack, frame.cull_lod.w), kept);
}

// Whether `slot` draws a blade (its bucket counts, before they become offsets).
bool slot_draws(uint slot) {
    uint sum = 0u;
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        sum += slot_counts[slot * SLOT_WORDS + b];
    }
    return sum > 0u;
}

// Lane 0, once the totals and the scale are known: each bucket thinned by the capacity scale,
// which makes every bucket fit the list's cull_lod.w entries (the room left is a guard that never
// cuts), padded to whole instances, at its place in the list (every class's buckets, one after
// another); its instance's draw (`bucket_draw`).
void place_buckets() {
    const uint batch = BLADES_PER_INSTANCE;
    uint first = 0u;
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        uint room = frame.cull_lod.w - min(first, frame.cull_lod.w);
        uint count = b < draw_buckets() ? min(thin_position(totals[b], thin_scale), room / batch * batch) : 0u;
        bucket_first[b] = first;
        bucket_count[b] = count;
        bucket_wanted[b] = totals[b];
        bucket_draws[b] = b < draw_buckets() ? bucket_draw(b) : uvec2(0u);
        first += (count + batch - 1u) / batch * batch;
    }
}

// Lane 0, once the buckets are placed: one indirect draw per LOD bucket (padding each bucket's
// last instance), the pose and levels passes' dispatch over each bucket, and the emit pass's
// dispatch over the slots that draw.
void write_dispatches() {
    // Each instance draws BLADES_PER_INSTANCE consecutive entries of the list (the bucket's
    // blade triangle list repeated, blade.vert), so a bucket starts at a multiple of it and its
    // last instance's tail is padded with VISIBLE_PADDING entries, which draw nothing.
    const uint batch = BLADES_PER_INSTANCE;
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        uint first = bucket_first[b];
        uint count = bucket_count[b];
        // The frame's counts report what is drawn (`STAT_WANTED` what was kept before thinning).
        totals[b] = count;
        uint instances = (count + batch - 1u) / batch;
        for (uint pad = first + count; pad < first + instances * batch; pad++) {
            visible[pad] = uvec2(VISIBLE_PADDING, 0u);
        }
        // VkDrawIndexedIndirectCommand: indexCount, instanceCount, firstIndex, vertexOffset,
        // firstInstance.
        draws[DRAW_WORDS * b] = bucket_draws[b].x;
        draws[DRAW_WORDS * b + DRAW_INSTANCES] = instances;
        draws[DRAW_WORDS * b + 2u] = bucket_draws[b].y;
        draws[DRAW_WORDS * b + 3u] = 0u;
        draws[DRAW_WORDS * b + DRAW_FIRST_INSTANCE] = first / batch;
        // The blade-pose and levels passes run one dispatch per bucket (its pipeline specialised
        // for its segments), an invocation per entry, padding included.
        draws[BUCKET_DISPATCH_WORD + 3u * b] = (instances * batch + POSE_GROUP - 1u) / POSE_GROUP;
        draws[BUCKET_DISPATCH_WORD + 3u * b + 1u] = 1u;
        draws[BUCKET_DISPATCH_WORD + 3u * b + 2u] = 1u;
        if (TILE_ROWS_CAPACITY > 0u) {
            tile_rows[b] = bucket_rows(b) ? bucket_tiles[b] : 0u;
        }
    }
    // The emit pass runs over the slots that draw: most of the rings are empty (off screen, too
    // far, outside the field), and a workgroup costs llvmpipe about 1.7 µs even when it returns
    // at once (4 ms for the 2401 slots of a 1M-blade field).
    draws[EMIT_DISPATCH_WORD] = drawing_slots;
    draws[EMIT_DISPATCH_WORD + 1u] = 1u;
    draws[EMIT_DISPATCH_WORD + 2u] = 1u;
    draws[THIN_WORD] = thin_scale;
}

// Row `k` of bucket `b` (per-tile rows): the draw of slot `slot`'s `count` blades of the bucket,
// the `offset`-th of the bucket's sequence on. The emit pass puts the sequence's entry j at
// bucket_first + thin_position(j) when thin_kept(j) (cull.glsl), so the slot's kept blades are the
// contiguous entries from thin_position(offset) to thin_position(offset + count). The draw covers
// the instances they fall in; blade.vert's variant `tiles` skips the entries of the instances'
// other tiles (the record's range), so each entry is drawn once, by its own tile's draw.
void write_tile_row(uint b, uint k, uint slot, uint offset, uint count) {
    const uint batch = BLADES_PER_INSTANCE;
    uint end = bucket_first[b] + min(thin_position(offset + count, thin_scale), bucket_count[b]);
    uint first = min(bucket_first[b] + thin_position(offset, thin_scale), end);
    uint at = tile_command_word(b, k);
    tile_rows[at] = bucket_draws[b].x;
    tile_rows[at + DRAW_INSTANCES] = end > first ? (end - 1u) / batch - first / batch + 1u : 0u;
    tile_rows[at + 2u] = bucket_draws[b].y;
    tile_rows[at + 3u] = 0u;
    tile_rows[at + DRAW_FIRST_INSTANCE] = first / batch;
    uint record = tile_record_word(b, k);
    tile_rows[record] = first;
    tile_rows[record + 1u] = end;
    tile_rows[record + 2u] = slot;
}

void main() {
    read_cull_settings();
    uint lane = gl_LocalInvocationID.x;
    uint slots = frame.cull_tiles.y;
    uint run = (slots + SCAN - 1u) / SCAN;
    uint begin = min(lane * run, slots);
    uint end = min(begin + run, slots);
    uint own[SLOT_WORDS] = uint[](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    uint own_slots = 0u;
    uint own_lost = 0u;
    uint own_tiles[MAX_LOD_BUCKETS] = uint[](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    for (uint slot = begin; slot < end; slot++) {
        for (uint w = 0u; w < SLOT_WORDS; w++) {
            own[w] += slot_counts[slot * SLOT_WORDS + w];
        }
        if (TILE_ROWS_CAPACITY > 0u) {
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                own_tiles[b] += bucket_rows(b) && slot_counts[slot * SLOT_WORDS + b] > 0u ? 1u : 0u;
            }
        }
        own_slots += slot_draws(slot) ? 1u : 0u;
        // A slot past the verdicts' room (cull_tiles.comp): its candidates were not tested.
        bool no_room = verdict_base(slot) == NO_ROOM;
        own_lost += no_room ? slot_candidates(slot) : 0u;
    }
    run_slots[lane] = own_slots;
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        run_start[b][lane] = own[b];
        run_tiles[b][lane] = own_tiles[b];
    }
    if (lane < SLOT_WORDS) {
        totals[lane] = 0u;
    }
    if (lane == 0u) {
        lost_to_room = 0u;
    }
    barrier();
    if (lane == 0u) {
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            uint sum = 0u;
            for (uint i = 0u; i < SCAN; i++) {
                uint count = run_start[b][i];
                run_start[b][i] = sum;
                sum += count;
            }
            totals[b] = sum;
        }
        uint listed = 0u;
        for (uint i = 0u; i < SCAN; i++) {
            uint count = run_slots[i];
            run_slots[i] = listed;
            listed += count;
        }
        drawing_slots = listed;
        uint kept = 0u;
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            kept += totals[b];
        }
        wanted = kept;
        thin_scale = capacity_scale(kept);
        place_buckets();
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            uint sum = 0u;
            for (uint i = 0u; TILE_ROWS_CAPACITY > 0u && i < SCAN; i++) {
                uint count = run_tiles[b][i];
                run_tiles[b][i] = sum;
                sum += count;
            }
            bucket_tiles[b] = sum;
        }
    }
    for (uint w = MAX_LOD_BUCKETS; w < SLOT_WORDS; w++) {
        atomicAdd(totals[w], own[w]);
    }
    atomicAdd(lost_to_room, own_lost);
    barrier();
    uint at[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        at[b] = run_start[b][lane];
    }
    uint row[MAX_LOD_BUCKETS];
    for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
        row[b] = run_tiles[b][lane];
    }
    uint listed = run_slots[lane];
    for (uint slot = begin; slot < end; slot++) {
        if (slot_draws(slot)) {
            draws[EMIT_SLOTS_WORD + listed] = slot;
            listed += 1u;
        }
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            // Offset of this slot's blades inside bucket b: the slots before it in slot order (near
            // to far), or after it for a class drawn far to near.
            uint count = slot_counts[slot * SLOT_WORDS + b];
            bool reversed = bucket_far_to_near(b);
            uint offset = reversed ? bucket_wanted[b] - at[b] - count : at[b];
            slot_counts[slot * SLOT_WORDS + b] = offset;
            if (bucket_rows(b) && count > 0u) {
                write_tile_row(b, reversed ? bucket_tiles[b] - 1u - row[b] : row[b], slot, offset, count);
                row[b] += 1u;
            }
            at[b] += count;
        }
    }
    if (lane == 0u) {
        write_dispatches();
    }
    barrier();
    if (lane < SLOT_WORDS) {
        cull_stats[lane] = totals[lane];
    }
    if (lane == 0u) {
        cull_stats[STAT_WANTED] = wanted;
        cull_stats[STAT_SCALE] = thin_scale;
        cull_stats[STAT_NO_ROOM] = lost_to_room;
        uint rows = 0u;
        for (uint b = 0u; TILE_ROWS_CAPACITY > 0u && b < draw_buckets(); b++) {
            rows += bucket_rows(b) ? bucket_tiles[b] : 0u;
        }
        cull_stats[STAT_TILE_DRAWS] = rows;
    }
}
