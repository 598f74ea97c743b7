#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 2 of 3: one workgroup turns the per-slot bucket counts into offsets (an exclusive
// prefix sum over the slots, in slot order: near to far), writes one indirect draw per LOD bucket
// (its instances are bucket b's blades, from firstInstance = the blades of the buckets before it)
// and sums the frame's counts into the host-visible `cull_stats` (read after the frame's fence).
#include "cull.glsl"

const uint SCAN = 256u;
layout(local_size_x = SCAN) in;

shared uint scan[MAX_LOD_BUCKETS][SCAN];
shared uint running[MAX_LOD_BUCKETS];
shared uint totals[SLOT_WORDS];

void main() {
    uint lane = gl_LocalInvocationID.x;
    uint slots = frame.cull_tiles.y;
    if (lane < SLOT_WORDS) {
        totals[lane] = 0u;
    }
    if (lane < MAX_LOD_BUCKETS) {
        running[lane] = 0u;
    }
    uint stats[SLOT_WORDS - MAX_LOD_BUCKETS];
    for (uint s = 0u; s < SLOT_WORDS - MAX_LOD_BUCKETS; s++) {
        stats[s] = 0u;
    }
    barrier();
    for (uint base = 0u; base < slots; base += SCAN) {
        uint slot = base + lane;
        uint own[MAX_LOD_BUCKETS];
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            own[b] = slot < slots ? slot_counts[slot * SLOT_WORDS + b] : 0u;
            scan[b][lane] = own[b];
        }
        if (slot < slots) {
            for (uint s = MAX_LOD_BUCKETS; s < SLOT_WORDS; s++) {
                stats[s - MAX_LOD_BUCKETS] += slot_counts[slot * SLOT_WORDS + s];
            }
        }
        barrier();
        // Hillis-Steele inclusive scan of the chunk, every bucket at once.
        for (uint step = 1u; step < SCAN; step <<= 1) {
            uint add[MAX_LOD_BUCKETS];
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                add[b] = lane >= step ? scan[b][lane - step] : 0u;
            }
            barrier();
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                scan[b][lane] += add[b];
            }
            barrier();
        }
        if (slot < slots) {
            for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
                // Exclusive offset of this slot's blades inside bucket b.
                slot_counts[slot * SLOT_WORDS + b] = running[b] + scan[b][lane] - own[b];
            }
        }
        barrier();
        if (lane < MAX_LOD_BUCKETS) {
            running[lane] += scan[lane][SCAN - 1u];
        }
        barrier();
    }
    for (uint s = 0u; s < SLOT_WORDS - MAX_LOD_BUCKETS; s++) {
        atomicAdd(totals[MAX_LOD_BUCKETS + s], stats[s]);
    }
    barrier();
    if (lane == 0u) {
        uint first = 0u;
        for (uint b = 0u; b < MAX_LOD_BUCKETS; b++) {
            uint count = b < frame.cull_lod.x ? running[b] : 0u;
            // VkDrawIndirectCommand: vertexCount, instanceCount, firstVertex, firstInstance.
            draws[4u * b] = 2u * (bucket_segments(b) + 1u);
            draws[4u * b + 1u] = count;
            draws[4u * b + 2u] = 0u;
            draws[4u * b + 3u] = first;
            first += count;
            totals[b] = count;
        }
    }
    barrier();
    if (lane < SLOT_WORDS) {
        cull_stats[lane] = totals[lane];
    }
}
