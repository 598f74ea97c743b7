// The pressed map (issue #34, `render::animation::pressed`): trampling that stays and recovers, and
// cutting that regrows. A world-space grid of PRESSED_DIMS² cells of PRESSED_CELL metres that
// follows the camera (its window of cells round the eye), each cell in slot (world cell mod
// PRESSED_DIMS) with its world cell as a tag, so a cell keeps its value while the window scrolls
// and one that left reads as never pressed. A cell holds the bend its last press left (its
// direction times its amount, 0 to 1), that press's time, and the time of the last cut; the
// bend recovers as a critically damped spring and the cut regrows, both in closed form
// (`pressed_bend`, `pressed_length`), so any frame rate gives the same map. The press pass writes
// it (animation/press.comp), the push-out pass reads it for every posed blade (push_out.comp),
// the far field for its plants' fragments (far_field/far.frag, variant `pressed`).
// Its two resources are in the includer's own set, from binding PRESSED_BINDING, by name
// (`PressedCells`, `PressedFrame`).
#ifndef MEADOW_PRESSED_GLSL
#define MEADOW_PRESSED_GLSL

#ifndef PRESSED_BINDING
#define PRESSED_BINDING 1
#endif
// `readonly` for a reader in a stage that may not write storage (the far field's fragments).
#ifndef PRESSED_ACCESS
#define PRESSED_ACCESS
#endif

const uint PRESSED_DIMS = 512u;     // render::animation::pressed::DIMS
const float PRESSED_CELL = 0.25;    // render::animation::pressed::CELL_M
const uint PRESSED_SWEEPS = 2u * MAX_COLLIDERS; // render::animation::pressed::MAX_SWEEPS
const float PRESSED_STUB = 0.2;     // render::animation::pressed::STUB: a cut blade's length, of its own
const float PRESSED_REACH = 1.2;    // render::animation::pressed::REACH_M: a collider presses below this height
const float PRESSED_LEAN_DEG = 70.0; // render::animation::pressed::LEAN_DEG: a full press's lean

// A cell: the bend at the press (x, z as half floats), the press's time, the cut's time, and its
// tag (0: never written).
layout(set = SET_PASS, binding = PRESSED_BINDING, std430) PRESSED_ACCESS buffer PressedCells { uvec4 pressed_cells[]; };

// `render::animation::pressed::PressedFrame`, written by the CPU for the frame.
layout(set = SET_PASS, binding = PRESSED_BINDING + 1, std430) readonly buffer PressedFrame {
    uvec4 pressed_counts;  // x sweeps, y 1 when the map is read this frame, z the press dispatch's cells, w unused
    ivec4 pressed_window;  // xy the window's first world cell, zw unused
    ivec4 pressed_origin;  // xy O's world cell (of PRESSED_CELL), zw unused
    vec4 pressed_offset;   // xy O less its cell's corner (m), zw unused
    vec4 pressed_times;    // x now, y the previous frame's time, z the spring's rate ω (1/s), w the regrowth (s)
    vec4 pressed_sweeps[3u * PRESSED_SWEEPS]; // per collider: centre then and now (xyz relative to O), radii (w: 1 cuts)
    ivec4 pressed_boxes[PRESSED_SWEEPS]; // per collider: the first world cell its sweep covers, the box's width, its first invocation
    // The push-out pass's interaction patches (`render::animation::patches::PatchFrame`; zero for
    // the press pass, animation/patches.glsl reads them).
    uvec4 patch_steps;     // x the step the previous frame drew plus one (0: restart), y steps to take, z this frame's step plus one, w 1 when patches run
    vec4 patch_chain;      // x the step (s), y the chain's stiffness k/J (1/s²), z its damper d/J (1/s), w unused
};

// The tag of world cell `w`: never 0.
uint pressed_tag(ivec2 w) {
    return 1u + ((uint(w.x) & 0x7fffu) << 15u | (uint(w.y) & 0x7fffu));
}

// The world cell under `p` (x, z relative to O).
ivec2 pressed_world_cell(vec2 p) {
    return pressed_origin.xy + ivec2(floor((p + pressed_offset.xy) / PRESSED_CELL));
}

// The centre of world cell `w`, relative to O.
vec2 pressed_cell_centre(ivec2 w) {
    return vec2(w - pressed_origin.xy) * PRESSED_CELL - pressed_offset.xy + 0.5 * PRESSED_CELL;
}

// The slot of world cell `w`, or PRESSED_DIMS² when it lies outside the window.
uint pressed_slot(ivec2 w) {
    ivec2 local = w - pressed_window.xy;
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, ivec2(PRESSED_DIMS)))) {
        return PRESSED_DIMS * PRESSED_DIMS;
    }
    uvec2 s = uvec2(w & ivec2(PRESSED_DIMS - 1u));
    return s.y * PRESSED_DIMS + s.x;
}

// The critically damped spring's share of a displacement left `tau` seconds after its press,
// at rest then: (1 + ω τ) e^(−ω τ), 5 % at --recovery-s (ω = 4.744 / recovery).
float pressed_recovery(float tau) {
    float wt = max(tau, 0.0) * pressed_times.z;
    return (1.0 + wt) * exp(-wt);
}

// The bend at `p` now (direction times amount), and the blade's length as a share of its own
// (PRESSED_STUB just cut, 1 regrown), from the cell under it.
vec3 pressed_at(vec2 p) {
    ivec2 w = pressed_world_cell(p);
    uint slot = pressed_slot(w);
    if (slot >= PRESSED_DIMS * PRESSED_DIMS) {
        return vec3(0.0, 0.0, 1.0);
    }
    uvec4 cell = pressed_cells[slot];
    if (cell.w != pressed_tag(w)) {
        return vec3(0.0, 0.0, 1.0);
    }
    float now = pressed_times.x;
    vec2 bend = unpackHalf2x16(cell.x) * pressed_recovery(now - uintBitsToFloat(cell.y));
    float since_cut = now - uintBitsToFloat(cell.z);
    float grown = clamp(since_cut / pressed_times.w, 0.0, 1.0);
    return vec3(bend, mix(PRESSED_STUB, 1.0, grown));
}

// Bend and shorten the backbone `points` (world, the root first) by `pressed` (`pressed_at`): each
// point's offset from the root scaled by the length (a cut), then turned about the root towards
// the bend's direction by 2 asin(amount · sin(PRESSED_LEAN_DEG / 2)), so every point's
// displacement is linear in the amount (a tip back to 5 % of its displacement at 5 % of the bend).
void press_points(inout vec3 points[MAX_SEGMENTS + 1u], vec3 pressed) {
    vec3 root = points[0];
    float amount = length(pressed.xy);
    vec3 dir = amount > 1e-6 ? vec3(pressed.x, 0.0, pressed.y) / amount : vec3(1.0, 0.0, 0.0);
    vec3 axis = normalize(cross(vec3(0.0, 1.0, 0.0), dir));
    float turn = 2.0 * asin(min(amount, 1.0) * sin(0.5 * radians(PRESSED_LEAN_DEG)));
    float c = cos(turn);
    float s = sin(turn);
    for (uint level = 1u; level <= MODEL_SEGMENTS; level++) {
        vec3 v = (points[level] - root) * pressed.z;
        // Rodrigues' rotation about `axis`.
        points[level] = root + v * c + cross(axis, v) * s + axis * dot(axis, v) * (1.0 - c);
    }
}

#endif
