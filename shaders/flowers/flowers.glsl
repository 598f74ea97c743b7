// Flowers among the blades (`scene::flowers`, `render::flowers`): which candidate blades the cull
// claims for the flowers, and each flower's stem and head, shared by the count pass
// (flowers_count.comp) and the flowers' pass (flower.vert). The includer includes
// common/bindings.glsl and common/field.glsl first.
#ifndef MEADOW_FLOWERS_GLSL
#define MEADOW_FLOWERS_GLSL

const uint FLOWER_STORED_KEY = 0x5157u; // scene::flowers::STORED_KEY
const float FLOWER_STEM_SHORTEST = 0.40; // scene::flowers::STEM_SHORTEST_M
const float FLOWER_STEM_WIDTH = 0.004; // scene::flowers::STEM_WIDTH_M
const float FLOWER_HEAD_SMALLEST = 0.025; // scene::flowers::HEAD_SMALLEST_M
const float FLOWER_HEAD_LARGEST = 0.045; // scene::flowers::HEAD_LARGEST_M
const float FLOWER_NEAR_PIXELS = 8.0; // scene::flowers::NEAR_PIXELS
const uint FLOWER_NEAR_PETALS = 6u; // scene::flowers::NEAR_PETALS
const uint FLOWER_NEAR_STEM_SEGMENTS = 4u; // scene::flowers::NEAR_STEM_SEGMENTS

// `scene::flowers::flower_hash`.
uint flower_hash(uint a, uint b) {
    uint h = (a * 0x9e3779b1u) ^ ((b + 0x7f4a7c15u) * 0x85ebca77u);
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    return h ^ (h >> 16u);
}

// The hash of a candidate: in a block field, of its world cell `cell` (the cell's hash, which
// repeats with the world) and its blade `index` in the block; of a stored blade's `index`.
uint flower_candidate_hash(ivec2 cell, uint index) {
    return (RENDER_FLAGS & FLAG_BLOCKS) != 0u ? flower_hash(cell_hash(cell), index) : flower_hash(FLOWER_STORED_KEY, index);
}

// The same for the candidate whose visible-list id is `id` (`visible_blade`: a block field's ring
// slot and blade in the block, or a stored blade's index).
uint flower_id_hash(uint id) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        return flower_candidate_hash(frame_values.field_cells.xy + ring_cell(id >> 16), id & 0xffffu);
    }
    return flower_candidate_hash(ivec2(0), id);
}

// Whether the candidate of hash `hash` rooted at `at` (relative to O) is a flower
// (`scene::flowers::claimed`): its hash under FLOWER_SHARE times the flowers' cover over the
// grass's there.
bool flower_claimed(uint hash, vec2 at) {
    if (FLOWER_SHARE == 0u) {
        return false;
    }
    vec2 covers = ground_covers(at);
    float q = min(uintBitsToFloat(FLOWER_SHARE) * covers.y / max(covers.x, 1.0 / 255.0), 1.0);
    return float(hash >> 8u) / 16777216.0 < q;
}

// A flower's looks, from its hash (a second hash: the claim used the first's high bits).
struct FlowerLooks {
    float stem_height; // m
    float head_radius; // m
    uint color;        // into HEAD_COLORS
    float turn;        // the petals' turn about the stem (radians)
};

FlowerLooks flower_looks(uint hash) {
    uint h = flower_hash(hash, 1u);
    FlowerLooks looks;
    looks.stem_height = mix(FLOWER_STEM_SHORTEST, TALLEST_BLADE, float(h & 0xffu) / 255.0);
    looks.head_radius = mix(FLOWER_HEAD_SMALLEST, FLOWER_HEAD_LARGEST, float((h >> 8u) & 0xffu) / 255.0);
    looks.color = ((h >> 16u) & 0xffu) % 5u;
    looks.turn = float(h >> 24u) / 255.0 * 2.0 * PI;
    return looks;
}

// `scene::flowers::HEAD_COLORS`.
vec3 flower_head_color(uint i) {
    const vec3 colors[5] = vec3[5](vec3(0.80, 0.80, 0.74), vec3(0.85, 0.62, 0.06), vec3(0.38, 0.16, 0.62),
        vec3(0.75, 0.10, 0.16), vec3(0.18, 0.28, 0.78));
    return colors[min(i, 4u)];
}

#endif
