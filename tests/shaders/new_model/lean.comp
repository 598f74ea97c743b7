#version 460
#extension GL_GOOGLE_include_directive : require
// tests/new_model.rs: a blade response defined outside the library. Once per drawn blade (with
// the cull, one dispatch per LOD bucket over its visible list) it samples the wind field at the
// blade's root (wind/wind_field.glsl) and bends the blade along it: the tip moves by `lean.x`
// blade heights per m/s of wind, at most `lean.y`, along a parabola from the upright root. It
// writes the renderer's pose records (set SET_POSES, bindings.glsl's `POSE_WRITER`) in the
// blade's frame, as blade_pose.comp's format says; its own set holds the cull's `Draws` and its
// uniform block `Lean`.
#define POSE_WRITER
#include "common/bindings.glsl"
#include "wind/wind_field.glsl"
#include "animation/pose_write.glsl"

// The cull's scan sizes the buckets' dispatches for POSE_GROUP invocations a workgroup.
layout(local_size_x = POSE_GROUP) in;

// The response's uniform block, in its pass's own set (`Draws` is binding 0 there).
layout(set = SET_PASS, binding = 1, std140) uniform Lean {
    vec4 lean; // x tip offset in heights per m/s, y the most, zw unused
};

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    vec2 wind = wind_at_blade(blade_index, blade.position.xz).xz;
    vec2 offset = wind * lean.x;
    float reach = length(offset);
    if (reach > lean.y) {
        offset *= lean.y / reach;
    }
    // Into the blade's frame (place_level: x across, z along the normal).
    vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
    vec2 normal_dir = vec2(sin(blade.facing), cos(blade.facing));
    vec2 local = vec2(dot(offset, across), dot(offset, normal_dir));
    uint base = pose_base(i);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        float t = float(level) / float(MODEL_SEGMENTS);
        // Over the blade's height and POSE_SCALE, as the records store it.
        vec3 unit = vec3(local.x * t * t, t, local.y * t * t) / POSE_SCALE;
        vec3 tangent = normalize(vec3(2.0 * local.x * t, 1.0, 2.0 * local.y * t));
        write_pose_level(base, level, unit, tangent, vec2(1.0, 0.0), 0.0);
    }
}
