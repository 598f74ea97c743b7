// Interaction patches (Belyaev §3.4; `render::animation::patches` gives the design): blades within
// reach of a collider switch to the inertial chain (§3.1, animation/chain.glsl) and hand back once
// they settle, or time out through a blend. Only they hold state: a hash table of records keyed on
// the blade, and before it a presence grid over the pressed map's cells (animation/pressed.glsl,
// same slots) holding the time until which a patch in a cell may live. The includer has included
// animation/pressed.glsl (its frame block carries the patches' part, `patch_steps`,
// `patch_chain`), animation/collider_bins.glsl and animation/chain.glsl; the store and the list of
// blades to patch are in its own set from binding PATCHES_BINDING, by name (`Patches`,
// `PatchList`).
#ifndef MEADOW_PATCHES_GLSL
#define MEADOW_PATCHES_GLSL

#ifndef PATCHES_BINDING
#define PATCHES_BINDING 3
#endif

const uint PATCH_CAPACITY = 65536u;    // render::animation::patches::CAPACITY (a power of two)
const uint PATCH_WINDOW = 16u;         // render::animation::patches::WINDOW
const uint PATCH_HEADER_WORDS = 8u;    // render::animation::patches::HEADER_WORDS
const uint PATCH_RECORD_WORDS = 32u;   // render::animation::patches::RECORD_WORDS
const float PATCH_REACH = 0.1;         // render::animation::patches::REACH_M
const float PATCH_TIMEOUT = 1.5;       // render::animation::patches::TIMEOUT_S
const float PATCH_BLEND = 0.5;         // render::animation::patches::BLEND_S
const float PATCH_SETTLED = 0.5;       // render::animation::patches::SETTLED_RAD_S
const uint PATCH_NONE = 0xffffffffu;

// The presence grid (PRESSED_DIMS² words, f32 times), then PATCH_CAPACITY records: the blade (two
// words: its world cell packed 16 | 16, 0 in a stored field; its index plus one), its step plus one
// (0: free), its blend to the cheap pose, seconds since its last contact, three unused, then per
// joint ψ and ω.
layout(set = SET_PASS, binding = PATCHES_BINDING, std430) buffer Patches { uint patches[]; };

// A blade's key: a stored blade's index, a block field's world cell and index in its block.
uvec2 patch_key(uvec2 entry, uint blade_index) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        ivec2 cell = frame.field_cells.xy + ring_cell(entry.x >> 16);
        return uvec2((uint(cell.x) & 0xffffu) << 16 | (uint(cell.y) & 0xffffu), blade_index + 1u);
    }
    return uvec2(0u, blade_index + 1u);
}

// Whether a patch may live in the pressed-map cell under `p` (x, z relative to O) now.
bool patch_may_live(vec2 p) {
    uint slot = pressed_slot(pressed_world_cell(p));
    return slot < PRESSED_DIMS * PRESSED_DIMS && uintBitsToFloat(patches[slot]) > pressed_times.x;
}

// A patch in the cell under `p` may live until `until` (s; times are never negative, so their bits
// order as the times do).
void patch_lives_until(vec2 p, float until) {
    uint slot = pressed_slot(pressed_world_cell(p));
    if (slot < PRESSED_DIMS * PRESSED_DIMS) {
        atomicMax(patches[slot], floatBitsToUint(until));
    }
}

// The first word of slot `slot`'s record.
uint patch_record(uint slot) {
    return PRESSED_DIMS * PRESSED_DIMS + slot * PATCH_RECORD_WORDS;
}

// The record of `key`, or with `claim` a free one claimed for it (its step word set to this frame's);
// PATCH_NONE if it has none (or finds its window full). `carried`: the record holds the previous
// frame's step of this blade. A record is free when its step is neither the previous frame's nor
// this one's.
uint patch_find(uvec2 key, bool claim, out bool carried) {
    uint h = key.x * 0x9e3779b1u ^ key.y * 0x85ebca77u;
    h ^= h >> 15u;
    h *= 0x2c1b3c6du;
    h ^= h >> 12u;
    uint from = patch_steps.x;
    uint to = patch_steps.z;
    carried = false;
    for (uint i = 0u; i < PATCH_WINDOW; i++) {
        uint base = patch_record((h + i) & (PATCH_CAPACITY - 1u));
        uint step = patches[base + 2u];
        if (from != 0u && step == from && patches[base] == key.x && patches[base + 1u] == key.y) {
            carried = true;
            return base;
        }
    }
    if (!claim) {
        return PATCH_NONE;
    }
    for (uint i = 0u; i < PATCH_WINDOW; i++) {
        uint base = patch_record((h + i) & (PATCH_CAPACITY - 1u));
        uint step = patches[base + 2u];
        bool free = step != to && (step != from || from == 0u);
        // Another blade may claim it first: then on to the next.
        if (free && atomicCompSwap(patches[base + 2u], step, to) == step) {
            patches[base] = key.x;
            patches[base + 1u] = key.y;
            return base;
        }
    }
    return PATCH_NONE;
}

void patch_read(uint base, out ChainState c) {
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        uint at = base + PATCH_HEADER_WORDS + 6u * k;
        c.psi[k] = uintBitsToFloat(uvec3(patches[at], patches[at + 1u], patches[at + 2u]));
        c.omega[k] = uintBitsToFloat(uvec3(patches[at + 3u], patches[at + 4u], patches[at + 5u]));
    }
}

// The record holds this frame's step: its state, its blend and its time since the last contact.
void patch_write(uint base, ChainState c, float blend, float idle) {
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        uint at = base + PATCH_HEADER_WORDS + 6u * k;
        uvec3 psi = floatBitsToUint(c.psi[k]);
        uvec3 omega = floatBitsToUint(c.omega[k]);
        patches[at] = psi.x;
        patches[at + 1u] = psi.y;
        patches[at + 2u] = psi.z;
        patches[at + 3u] = omega.x;
        patches[at + 4u] = omega.y;
        patches[at + 5u] = omega.z;
    }
    patches[base + 2u] = patch_steps.z;
    patches[base + 3u] = floatBitsToUint(blend);
    patches[base + 4u] = floatBitsToUint(idle);
}

// The backbone `local` (blade frame, root at 0; the levels a blade of `segments` segments reads) at
// `f` of its levels, linear between the read levels either side.
vec3 backbone_at(vec3 local[MAX_SEGMENTS + 1u], uint segments, float f) {
    float x = f * float(MODEL_SEGMENTS);
    uint lo = 0u;
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        lo = level_read_in(segments, level) && float(level) <= x ? level : lo;
    }
    uint hi = MODEL_SEGMENTS;
    for (uint level = MODEL_SEGMENTS; level > lo; level--) {
        hi = level_read_in(segments, level) && float(level) >= x ? level : hi;
    }
    float t = hi > lo ? (x - float(lo)) / float(hi - lo) : 0.0;
    return mix(local[lo], local[hi], t);
}

// `s` with joints `first` and up turned, at rest, so that each segment lies along the backbone
// `local` (of a blade of `segments` segments) from k / CHAIN_SEGMENTS of its levels to
// (k + 1) / CHAIN_SEGMENTS: the shortest turn from the segment's rest frame on the one below (the
// hand-in from the cheap pose, and the chain held where push-out put it).
void chain_fit(Chain c, vec3 local[MAX_SEGMENTS + 1u], uint segments, uint first, inout ChainState s) {
    vec4 below = vec4(0.0, 0.0, 0.0, 1.0);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        vec4 rest = quat_mul(below, chain_rest(c, k));
        if (k >= first) {
            vec3 a = backbone_at(local, segments, float(k) / float(CHAIN_SEGMENTS));
            vec3 b = backbone_at(local, segments, float(k + 1u) / float(CHAIN_SEGMENTS));
            vec3 d = length(b - a) > 1e-7 ? quat_rotate(quat_inverse(rest), normalize(b - a)) : vec3(0.0, 1.0, 0.0);
            vec3 axis = cross(vec3(0.0, 1.0, 0.0), d);
            float len = length(axis);
            s.psi[k] = len > 1e-7 ? axis / len * atan(len, d.y) : vec3(0.0);
            s.omega[k] = vec3(0.0);
        }
        below = quat_mul(rest, quat_from_scaled_axis(s.psi[k]));
    }
}

// The drawn curve of the chain in state `s` at every model level (blade frame, root at 0).
void chain_points(Chain c, ChainState s, out vec3 local[MAX_SEGMENTS + 1u]) {
    vec4 frames[CHAIN_SEGMENTS];
    chain_frames(c, s, frames);
    vec3 p[3];
    chain_controls(c, frames, p);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        local[level] = bezier_point(vec3(0.0), p[0], p[1], p[2], float(level) / float(MODEL_SEGMENTS));
    }
}

// Whether the collider at emitter `e` has `blade` within reach of a patch: its root inside the
// ground ellipse grown by PATCH_REACH, and the collider's lowest point below the blade's top plus
// PATCH_REACH.
bool within_reach(uint e, BladeInstance blade) {
    vec2 q = (blade.position.xz - emitters[e].xz) / (emitters[e + 1u].xz + PATCH_REACH);
    return dot(q, q) < 1.0 && emitters[e].y - emitters[e + 1u].y < blade.position.y + blade.height + PATCH_REACH;
}

// The list the push-out walk appends to and the patch dispatch runs over
// (`render::animation::patch_pass`):
// the indirect dispatch's workgroups (x, y, z) and the blades appended (w), then per blade its
// pose record, its visible entry (x, y) and its bucket's segments, bit 31 set when a collider
// reaches it, bit 30 when a collider's ground circle holds its root.
layout(set = SET_PASS, binding = PATCHES_BINDING + 1, std430) buffer PatchList {
    uvec4 patch_list_head;
    uvec4 patch_list[];
};

const uint PATCH_REACHED = 0x80000000u;
const uint PATCH_HELD = 0x40000000u;
const uint PATCH_GROUP = 64u; // render::animation::patch_pass::PATCH_GROUP

#endif
