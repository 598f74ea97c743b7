#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 2 of 4: one workgroup per ring slot the tiles pass listed (cull_tiles.comp: the
// slots with candidates, and how many) runs the blade tests, writes each candidate's verdict to
// `cull_results` (from the slot's first verdict, `cull_alloc`), and how many candidates of its
// slot each bucket draws, and the counts after each test, to its `SLOT_WORDS` words of
// `slot_counts` (the tiles pass wrote the other slots'). Every word of every slot is written
// each frame: nothing accumulates across frames or workgroups, so there is no counter to clear.
// Each invocation counts in registers, then adds its counts into shared memory once: integer
// sums, whose result does not depend on the order the invocations run in.
#include "cull/cull.glsl"

// The blade class alone: a candidate is a blade, and the blade tests sort it into its LOD bucket.
// A set of draw classes brings a count shader of its own with its selection here.
int class_bucket(Frustum f, BladeTile tile, uint slot, uint rank, BladeInstance blade, vec3 normal, out uint failed, out vec2 scale) {
    return blade_bucket(f, blade, rank, tile.count, normal, failed, scale);
}

#include "cull/count_main.glsl"
