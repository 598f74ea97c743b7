// The blade-state store (`render::animation::blade_state::BladeStateStore`), for a stateful blade
// response's per-blade pass: where a drawn blade keeps its state, whether the record carries on
// from the step the previous frame drew, and how far the blade is into the hand-over to the
// response's stateless counterpart at the store's edge. The includer declares the cull's
// visible list and the frame (common/bindings.glsl, common/field.glsl); the store and this
// frame's block are in its own set (`SET_PASS`), from binding BLADE_STATE_BINDING of its
// numbering, given by name (`BladeStates`, `BladeStateFrame`).
#ifndef MEADOW_BLADE_STATE_GLSL
#define MEADOW_BLADE_STATE_GLSL

#ifndef BLADE_STATE_BINDING
#define BLADE_STATE_BINDING 2
#endif

// Records of HEADER_WORDS + words words: the world cell (x:16 | z:16, 0 in a stored field), the
// step the record holds plus one (0: never written), then the response's words.
layout(set = SET_PASS, binding = BLADE_STATE_BINDING, std430) buffer BladeStates { uint blade_states[]; };

// `render::animation::blade_state::StoreShape::frame_block`.
layout(set = SET_PASS, binding = BLADE_STATE_BINDING + 1, std140) uniform BladeStateFrame {
    uvec4 state_steps; // x the step the previous frame drew plus one (0: restart), y steps to take, z words per blade, w blades per block
    uvec4 state_grid;  // x radius in blocks, y blocks per side (2 radius + 1), z 1 for a block field, w the step this frame draws plus one
    vec4 state_time;   // x the step (s), yzw unused
};

// The same block through a storage binding of the same buffer: the values that decide control flow
// (the store's shape, the steps to take, whether the previous frame drew a step) are read from it,
// never from the uniform one (common/profile.glsl's rule: lavapipe inlines a uniform that alone
// decides a branch, and compiles a variant for each new value).
layout(set = SET_PASS, binding = BLADE_STATE_BINDING + 2, std430) readonly buffer BladeStateControl {
    uvec4 control_steps;
    uvec4 control_grid;
    vec4 control_time;
};

// The steps this frame takes (the loop bound of a stateful pass).
uint state_steps_to_take() {
    return control_steps.y;
}

const uint STATE_HEADER_WORDS = 2u; // render::animation::blade_state::HEADER_WORDS
const uint STATE_NONE = 0xffffffffu;

// `a` mod `m` (m > 0) in [0, m), for any `a` (GLSL leaves % of a negative operand undefined):
// world cell `w` sits in slot `w mod dims`, as `render::camera_grid::world_slot` places it.
int floor_mod(int a, int m) {
    int q = a >= 0 ? a / m : -((-(a + 1)) / m) - 1;
    return a - q * m;
}

// A drawn blade's place in the store.
struct BladeState {
    uint base;       // its record's first word, STATE_NONE outside the store
    uint key;        // its world cell, packed
    bool carried;    // the record holds the previous frame's step of this blade
    float stateless; // the weight of the stateless counterpart: 0 inside, 1 past the store
};

// The state of the blade at visible entry `entry` (with the cull), or stored blade `blade_index`
// (`entry` unused).
BladeState blade_state(uvec2 entry, uint blade_index) {
    BladeState s;
    s.key = 0u;
    s.stateless = 0.0;
    uint record;
    if (control_grid.z != 0u) {
        // (world cell, blade in block): the ring slot's cell as `visible_instance` finds it.
        ivec2 cell = frame_values.field_cells.xy + ring_cell(entry.x >> 16);
        ivec2 d = cell - frame_values.field_cells.xy;
        int radius = int(control_grid.x);
        int reach = max(abs(d.x), abs(d.y));
        // Across the outermost ring of blocks, by the blade's distance in blocks from the centre
        // of the camera's block (a block is `frame.field.x` metres; O is its corner).
        float edge = frame_values.field.x;
        BladeInstance placed = field_blade(cell, entry.x & 0xffffu);
        vec2 from_centre = abs(placed.position.xz - vec2(0.5 * edge)) / edge;
        s.stateless = clamp(max(from_centre.x, from_centre.y) - (float(radius) - 0.5), 0.0, 1.0);
        if (reach > radius) {
            s.base = STATE_NONE;
            s.carried = false;
            s.stateless = 1.0;
            return s;
        }
        int dims = int(state_grid.y);
        ivec2 slot = ivec2(floor_mod(cell.x, dims), floor_mod(cell.y, dims));
        record = uint(slot.y * dims + slot.x) * state_steps.w + (entry.x & 0xffffu);
        s.key = (uint(cell.x) & 0xffffu) << 16 | (uint(cell.y) & 0xffffu);
    } else {
        record = blade_index;
    }
    s.base = record * (STATE_HEADER_WORDS + state_steps.z);
    s.carried = control_steps.x != 0u && blade_states[s.base] == s.key && blade_states[s.base + 1u] == state_steps.x;
    return s;
}

// Word `i` of the blade's own state.
uint state_word(BladeState s, uint i) {
    return blade_states[s.base + STATE_HEADER_WORDS + i];
}

void set_state_word(BladeState s, uint i, uint value) {
    blade_states[s.base + STATE_HEADER_WORDS + i] = value;
}

// The record now holds this frame's step of this blade.
void state_written(BladeState s) {
    blade_states[s.base] = s.key;
    blade_states[s.base + 1u] = state_grid.w;
}

#endif
