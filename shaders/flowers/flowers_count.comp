#version 460
#extension GL_GOOGLE_include_directive : require
// The cull's count pass for the blade class and the flowers (`render::flowers`, a draw class):
// a candidate the flowers claim (flowers.glsl, `scene::flowers::claimed`) is tested as a flower,
// a stand-in blade as tall as its stem and head, with no edge-on test (a head shows from every
// side, `plant_bucket`), and goes to the flowers' near bucket while its head
// spans FLOWER_NEAR_PIXELS or more, their far bucket past that; every other candidate is the
// blade class's, in its LOD bucket. Flowers so thin with distance with the blades (the density
// LOD's rank test is the same).
#include "cull/cull.glsl"
#include "flowers/flowers.glsl"

int class_bucket(Frustum f, BladeTile tile, uint slot, uint rank, BladeInstance blade, vec3 normal, out uint failed, out vec2 scale) {
    // The slot's cell (invariant over the count pass's loop over the ranks) and the blade in it.
    ivec2 cell = frame_values.field_cells.xy + ring_cell(slot);
    uint hash = flower_candidate_hash(cell, (RENDER_FLAGS & FLAG_BLOCKS) != 0u ? rank : tile.first + rank);
    bool flower = flower_claimed(hash, blade.position.xz);
    FlowerLooks looks = flower_looks(hash);
    // One call of the tests for both, on selected inputs: on llvmpipe a branch some SIMD lanes
    // take runs for all of them, and two calls cost the count pass two tests per candidate.
    BladeInstance tested = blade;
    tested.height = flower ? looks.stem_height + looks.head_radius : blade.height;
    tested.width = flower ? 2.0 * looks.head_radius : blade.width;
    int bucket = plant_bucket(f, tested, rank, tile.count, normal, flower, failed, scale);
    float d = max(length(frame_values.cull_eye.xyz - blade.position), 1e-3);
    float pixels = 2.0 * looks.head_radius * frame_values.cull_eye.w / d;
    int flower_bucket = int(class_first_bucket(1u)) + (pixels >= FLOWER_NEAR_PIXELS ? 0 : 1);
    // No widening: a flower stands for itself, not for the flowers the density LOD dropped.
    scale.y = flower ? 1.0 : scale.y;
    return bucket >= 0 && flower ? flower_bucket : bucket;
}

#include "cull/count_main.glsl"
