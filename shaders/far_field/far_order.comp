#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's ordered compaction (`render::far_field::place_pass::FarPlacePass`, `--fade
// blend`): the placement's variant `ordered` wrote one slot of `staged` per lattice point, far to
// near (`render::far_field::order`), a width of 0 where no plant stands. One workgroup walks them
// in that order: each invocation counts the plants of its run of consecutive slots, a scan of the
// counts in shared memory gives each run its first place, and each run copies its plants there.
// The plants keep the order, and the draw's instance count is their number (at most the capacity).
#include "common/bindings.glsl"
#include "far_field/far_field.glsl"

const uint GROUP = 256u; // render::far_field::ORDER_GROUP
layout(local_size_x = 256) in;

layout(set = SET_PASS, binding = 1, std430) writeonly buffer FarPlants { FarPlant plants[]; };
layout(set = SET_PASS, binding = 2, std430) buffer FarDraw { uint draw[5]; };
layout(set = SET_PASS, binding = 4, std430) readonly buffer FarStaged { FarPlant staged[]; };

shared uint sums[GROUP];

void main() {
    uint points = far.counts.x * FAR_RING_SIDE * FAR_RING_SIDE;
    uint lane = gl_LocalInvocationID.x;
    uint run = (points + GROUP - 1u) / GROUP;
    uint begin = min(lane * run, points);
    uint end = min(begin + run, points);
    uint count = 0u;
    for (uint i = begin; i < end; i++) {
        count += staged[i].centre_width.w > 0.0 ? 1u : 0u;
    }
    // An inclusive scan of the runs' counts (Hillis and Steele).
    sums[lane] = count;
    barrier();
    for (uint offset = 1u; offset < GROUP; offset <<= 1u) {
        uint before = lane >= offset ? sums[lane - offset] : 0u;
        barrier();
        sums[lane] += before;
        barrier();
    }
    uint slot = sums[lane] - count;
    for (uint i = begin; i < end && slot < far.counts.z; i++) {
        if (staged[i].centre_width.w > 0.0) {
            plants[slot] = staged[i];
            slot++;
        }
    }
    if (lane == GROUP - 1u) {
        draw[1] = min(sums[lane], far.counts.z);
    }
}
