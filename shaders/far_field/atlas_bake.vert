#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's atlas bake (`render::far_field::atlas`): the block's own blades (the blades a
// block field repeats), neutral, seen from the side (along +z), orthographic. Tile k takes the
// blades rooted in the block's metre k along z, their roots' x folded into the tile's metre (each
// blade drawn three times, a metre apart, so the tile repeats without a seam); depth is the
// root's place in the metre. One blade per instance, a strip of BAKE_SEGMENTS segments (thesis
// 4.1's two Bézier splines). The push constant says the tile (low byte) and what is written
// (`output`, high byte: 0 the albedo, 1 the height along the blade).
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "blades/blade_place.glsl"
#include "far_field/far_field.glsl"

layout(push_constant) uniform BakePush {
    uint code;
} bake;

const uint BAKE_SEGMENTS = 8u;

layout(location = 0) out vec2 out_uv;        // u across the blade, v root to tip
layout(location = 1) flat out uvec2 out_blade; // x the blade's variation, y what is written

void main() {
    uint tile = bake.code & 0xffu;
    uint blade_index = uint(gl_InstanceIndex) / 3u;
    float copy = float(int(uint(gl_InstanceIndex) % 3u) - 1);
    BladeInstance blade = blade_record(blade_index);
    uint level = uint(gl_VertexIndex) >> 1;
    float side = float(uint(gl_VertexIndex) & 1u);
    float t = float(level) / float(BAKE_SEGMENTS);
    out_uv = vec2(side, t);
    out_blade = uvec2(blade.variation, bake.code >> 8);
    float slab = blade.position.z - float(tile);
    if (slab < 0.0 || slab >= 1.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    LevelPose pose;
    pose.local = bezier_point(p[0], p[1], p[2], p[3], t);
    pose.tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
    pose.twist_cs = vec2(1.0, 0.0);
    pose.force = 0.0;
    blade.position = vec3(fract(blade.position.x) + copy, 0.0, slab);
    PlacedLevel placed = place_level(blade, pose, vec2(1.0));
    vec3 at = placed.centre + placed.width_dir * ((side - 0.5) * placed.width);
    gl_Position = vec4(2.0 * at.x / FAR_TILE_WIDTH - 1.0, 1.0 - 2.0 * at.y / FAR_TILE_HEIGHT, clamp(at.z, 0.0, 1.0), 1.0);
}
