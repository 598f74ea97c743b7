#version 460
#extension GL_GOOGLE_include_directive : require
// Cull, step 1 of 4: one workgroup runs the tile tests of every ring slot (cull.glsl,
// `tile_candidates`), a SIMD lane per slot. A slot without candidates gets its `SLOT_WORDS` words
// here (the count pass skips it). Every slot's candidates go to `cull_alloc` (the count and
// emit passes read them: the tile tests run once per slot and frame), and the slots with
// candidates are listed in slot order (near to far) with the count pass's indirect dispatch:
// an empty workgroup costs llvmpipe about 0.9 µs, 5.6 ms over the 6 241 slots of an unbounded
// field at 150 m, most of them off screen. The slots take their verdicts' room by a prefix sum of
// their candidates in slot order: no atomics, no counter to clear.
// Invocation i walks the i-th contiguous run of slots, one invocation scans the run sums, then
// each invocation writes its run's list entries and room.
#include "cull/cull.glsl"

// The blade tiles alone. A set of draw classes with a candidate source of its own brings a tiles
// shader of its own: `#define CLASS_SOURCE`, its `source_candidates`, then this body.
#include "cull/tiles_main.glsl"
