#version 460
#extension GL_GOOGLE_include_directive : require
// Push-out (Zhang Xia §6.2; `render::animation::push_out`): after the blade response's pose pass,
// over the same blades (the cull's LOD buckets and the posed classes' buckets, or every stored
// blade), each blade whose root lies inside a collider's ground circle has its recorded backbone
// moved out of the collider (animation/push_out.glsl), whichever response wrote it, stateless or
// stateful. Before that, the pressed map's bend and cut (animation/pressed.glsl) are applied to
// every blade whose cell holds one. A blade neither touches is left to the bit; so is every level
// below the first one moved. A blade within reach of a collider, or where an interaction patch may
// still live (animation/patches.glsl), is listed for the patch pass instead (animation/patch.comp),
// which draws it by its patch and walks it the same way. The pass declares nothing (is not
// recorded) on frames with no collider, no patch alive and a map that reads as empty.
#define POSE_EDITOR
// The collider count decides the loops: read the frame as storage (bindings.glsl says why).
#define FRAME_FROM_STORAGE
#include "common/bindings.glsl"
#include "animation/pose_write.glsl"
#include "animation/push_out.glsl"
#include "animation/pressed.glsl"
#include "animation/collider_bins.glsl"
#include "animation/chain.glsl"
#include "animation/patches.glsl"

layout(local_size_x = POSE_GROUP) in;

// Blade `record`'s recorded backbone walked out of every collider whose ground circle holds its
// root; the levels from the first one moved written again.
void push_blade(uint record, BladeInstance blade, uvec4 near, vec3 pressed) {
    // The recorded backbone in the world (relative to the origin, as the emitters are).
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    float scale = POSE_SCALE * max(blade.height, 1e-6);
    uint base = pose_base(record);
    vec3 points[MAX_SEGMENTS + 1u];
    vec2 twists[MAX_SEGMENTS + 1u];
    float forces[MAX_SEGMENTS + 1u];
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        points[level] = blade.position;
        twists[level] = vec2(1.0, 0.0);
        forces[level] = 0.0;
        if (level_read(level)) {
            vec3 unit;
            vec4 tangent_force;
            read_pose_level(base, level, unit, twists[level], tangent_force);
            vec3 local = unit * scale;
            points[level] = blade.position + across * local.x + vec3(0.0, local.y, 0.0) + normal_dir * local.z;
            forces[level] = tangent_force.w;
        }
    }
    uint moved = (RENDER_FLAGS & (FLAG_DEBUG_PRESSED | FLAG_DEBUG_PATCHES)) != 0u ? 1u : MODEL_SEGMENTS + 1u;
    // The pressed map's bend and cut first (render::animation::pressed), then the colliders.
    if (pressed.z < 1.0 || dot(pressed.xy, pressed.xy) > 1e-10) {
        press_points(points, pressed);
        moved = 1u;
    }
    moved = min(moved, push_out_colliders(points, near));
    if (moved > MODEL_SEGMENTS) {
        return;
    }
    // The moved levels again, and the read level below the first one (its tangent turns too),
    // their tangents from the read levels either side.
    uint from = 0u;
    for (uint level = 1u; level <= MODEL_SEGMENTS; level++) {
        from = level_read(level) && level < moved ? level : from;
    }
    float inv = 1.0 / scale;
    uint below = 0u;
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read(level)) {
            continue;
        }
        uint above = level;
        for (uint next = MODEL_SEGMENTS; next > level; next--) {
            above = level_read(next) ? next : above;
        }
        if (level >= from) {
            // `--debug-view pressed`: every level again, the map's share in the force channel;
            // `--debug-view patches`: no chain's share (the patch pass writes the patched blades').
            float shown = (RENDER_FLAGS & FLAG_DEBUG_PRESSED) != 0u
                ? max(length(pressed.xy), (1.0 - pressed.z) / (1.0 - PRESSED_STUB))
                : forces[level];
            shown = (RENDER_FLAGS & FLAG_DEBUG_PATCHES) != 0u ? 0.0 : shown;
            vec3 t = points[above] - points[below];
            t = length(t) > 0.0 ? normalize(t) : vec3(0.0, 1.0, 0.0);
            vec3 offset = points[level] - blade.position;
            vec3 local = vec3(dot(offset, across), offset.y, dot(offset, normal_dir));
            vec3 tangent = vec3(dot(t, across), t.y, dot(t, normal_dir));
            write_pose_level(base, level, local * inv, tangent, twists[level], shown);
        }
        below = level;
    }
}

// List blade `record` (visible entry `entry`, drawn with its bucket's segments; `reach`: a collider
// reaches it, `held`: a collider's ground circle holds its root) for the patch pass; the dispatch
// grows to cover it. False past the list's capacity: the blade is walked here.
bool patch_append(uint record, uvec2 entry, bool reach, bool held) {
    uint i = atomicAdd(patch_list_head.w, 1u);
    if (i >= PATCH_CAPACITY) {
        return false;
    }
    uint segments = (RENDER_FLAGS & FLAG_CULLED) != 0u ? SEGMENTS : MODEL_SEGMENTS;
    patch_list[i] = uvec4(record, entry, segments | (reach ? PATCH_REACHED : 0u) | (held ? PATCH_HELD : 0u));
    atomicMax(patch_list_head.x, i / PATCH_GROUP + 1u);
    return true;
}

void main() {
    uint record;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    bool posed = posed_blade(record, entry, blade, blade_index);
    uint first = frame.wind_counts.x;
    // The colliders whose ground ellipse, grown by a patch's reach, may hold the root
    // (animation/collider_bins.glsl).
    uvec4 near = posed ? colliders_near(blade.position.xz) : uvec4(0u);
    bool held = false;
    bool reach = false;
    uvec4 each = near;
    while (each != uvec4(0u)) {
        uint e = first + 2u * next_collider(each);
        held = circle_holds(e, blade.position) || held;
        reach = within_reach(e, blade) || reach;
    }
    // A patch where a collider reaches the blade, or where one may still live: the patch pass's.
    bool patched = posed && patch_steps.w != 0u && (reach || patch_may_live(blade.position.xz));
    if (patched && patch_append(record, entry, reach, held)) {
        return;
    }
    vec3 pressed = vec3(0.0, 0.0, 1.0);
    if (pressed_counts.y != 0u && posed) {
        pressed = pressed_at(blade.position.xz);
    }
    held = held || pressed.z < 1.0 || dot(pressed.xy, pressed.xy) > 1e-10;
    // `--debug-view pressed` colours every posed blade by the map, `patches` by its patch.
    held = held || (posed && (RENDER_FLAGS & (FLAG_DEBUG_PRESSED | FLAG_DEBUG_PATCHES)) != 0u);
    // llvmpipe runs a branch's body under a mask even when no lane takes it (1.1 ms of this pass
    // at the default scene with no blade held), but leaves a loop once no lane is in it: the walk
    // is a loop of at most one turn, which a group of lanes no circle holds skips.
    for (uint turn = held ? 0u : 1u; turn < 1u; turn++) {
        push_blade(record, blade, near, pressed);
    }
}
