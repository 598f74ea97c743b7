#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's atlas bake (`render::far_field::atlas`): the block's own blades (the blades a
// block field repeats), neutral, seen from the side (along +z), orthographic. Tile k takes the
// blades rooted in the block's metre k along z, their roots' x folded into the tile's metre (each
// blade drawn three times, a metre apart, so the tile repeats without a seam); depth is the
// root's place in the metre. One blade per instance, a strip of BAKE_SEGMENTS segments (thesis
// 4.1's two Bézier splines). The push constant says the tile (bits 0-7), what is written (bits
// 8-15, `output`: 0 the albedo, 1 the height along the blade) and the flower tiles' share (bits
// 16-31, in 65535ths).
//
// With flowers (`--flowers`, FLOWER_SHARE), tiles 0 and 1 are grass alone, and in tiles 2 and 3
// the blades the flowers claim at the flower tiles' share are flowers (`scene::flowers`): a stem,
// 4 mm wide and of the flower's own height, in the blade's place; and the variant `heads` draws
// each one's head, the far head of the flowers' pass (a square as wide as the star's mean radius,
// facing along the stem's tip), 4 vertices a blade. The share is the most the cover grows for a
// grass's worth (`scene::Scene::far_flower_share`), and a far plant takes the flower tiles where
// the share at its place calls for them (far.vert): the far field's flowers follow the map's green.
// variant heads: BAKE_HEADS
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "common/field.glsl"
#include "common/ground.glsl"
#include "blades/blade_place.glsl"
#include "flowers/flowers.glsl"
#include "far_field/far_field.glsl"

layout(push_constant) uniform BakePush {
    uint code;
} bake;

const uint BAKE_SEGMENTS = 8u;

layout(location = 0) out vec2 out_uv;        // u across the blade, v root to tip
layout(location = 1) flat out uvec2 out_blade; // x the blade's variation (a head: its colour), y what is written (| BAKE_STEM)

// Bit of out_blade.y: a flower's stem, no outline.
const uint BAKE_STEM = 0x100u;

// Whether the block's blade `index` is a flower in tile `tile` of the atlas, and its looks.
bool baked_flower(uint index, uint tile, out FlowerLooks looks) {
    uint hash = flower_hash(FLOWER_STORED_KEY ^ 0xa71a5u, index);
    looks = flower_looks(hash);
    float share = float(bake.code >> 16u) / 65535.0;
    return FLOWER_SHARE != 0u && tile >= FAR_TILES / 2u && float(hash >> 8u) / 16777216.0 < share;
}

void main() {
    uint tile = bake.code & 0xffu;
    uint blade_index = uint(gl_InstanceIndex) / 3u;
    float copy = float(int(uint(gl_InstanceIndex) % 3u) - 1);
    BladeInstance blade = blade_record(blade_index);
    FlowerLooks looks;
    bool flower = baked_flower(blade_index, tile, looks);
#ifdef BAKE_HEADS
    uint level = BAKE_SEGMENTS;
    float side = 0.0;
#else
    uint level = uint(gl_VertexIndex) >> 1;
    float side = float(uint(gl_VertexIndex) & 1u);
#endif
    float t = float(level) / float(BAKE_SEGMENTS);
    out_uv = vec2(side, t);
    out_blade = uvec2(blade.variation, ((bake.code >> 8) & 0xffu) | (flower ? BAKE_STEM : 0u));
    float slab = blade.position.z - float(tile);
#ifdef BAKE_HEADS
    bool drawn = flower;
#else
    bool drawn = true;
#endif
    if (slab < 0.0 || slab >= 1.0 || !drawn) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 p[4];
    neutral_control_points(flower ? looks.stem_height : blade.height, unpack_variation(blade.variation, 2), p);
    LevelPose pose;
    pose.local = bezier_point(p[0], p[1], p[2], p[3], t);
    pose.tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
    pose.twist_cs = vec2(1.0, 0.0);
    pose.force = 0.0;
    blade.position = vec3(fract(blade.position.x) + copy, 0.0, slab);
    vec2 width = vec2(flower ? FLOWER_STEM_WIDTH / blade.width : 1.0, 1.0);
    PlacedLevel placed = place_level(blade, pose, width);
#ifdef BAKE_HEADS
    // The far head's square about the stem's tip, its corners in strip order (0, 1, 3, 2).
    vec3 axis = normalize(placed.tangent);
    vec3 ref = abs(axis.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 u = normalize(cross(axis, ref));
    const uint CORNERS[4] = uint[4](0u, 1u, 3u, 2u);
    float a = looks.turn + 0.5 * PI * float(CORNERS[uint(gl_VertexIndex) & 3u]);
    vec3 at = placed.centre + (cos(a) * u + sin(a) * cross(axis, u)) * (0.8 * looks.head_radius);
    out_blade.x = looks.color;
#else
    vec3 at = placed.centre + placed.width_dir * ((side - 0.5) * placed.width);
#endif
    gl_Position = vec4(2.0 * at.x / FAR_TILE_WIDTH - 1.0, 1.0 - 2.0 * at.y / FAR_TILE_HEIGHT, clamp(at.z, 0.0, 1.0), 1.0);
}
