#version 460
#extension GL_GOOGLE_include_directive : require
// The interaction patches (Belyaev §3.4; `render::animation::patch_pass`, the design in
// `render::animation::patches`): one invocation per blade the push-out walk listed
// (animation/push_out.comp). The blade's record is found, or claimed when a collider reaches it; its chain
// (animation/chain.glsl) is stepped from the record, or at hand-in fitted to the pose the cheap
// response recorded; the recorded pose becomes the chain's drawn curve, blended towards the cheap
// pose by the patch's blend; where a collider's ground circle holds the root, the chain is held
// where push-out moves that pose (its joints from the first moved fitted to it, their angular
// velocities zeroed).
// The record is written, or freed once the patch has settled or blended back. Then, as the push-out
// pass walks the blades it does not list (animation/push_out.comp), the pose is bent by the
// pressed map and walked out of the colliders, and every level the blade's bucket reads is written.
#define POSE_EDITOR
// The collider count decides the loops: read the frame as storage (bindings.glsl says why).
#define FRAME_FROM_STORAGE
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "animation/forces.glsl"
#include "animation/pose_write.glsl"
#include "animation/push_out.glsl"
#include "animation/pressed.glsl"
#include "animation/collider_bins.glsl"
#include "animation/chain.glsl"
#include "animation/patches.glsl"

layout(local_size_x = 64) in; // render::animation::patch_pass::PATCH_GROUP

// A blade's frame in the world: its root, across and normal (x and z of the blade frame).
struct BladeFrame {
    vec3 root;
    vec3 across;
    vec3 normal;
};

vec3 to_local(BladeFrame f, vec3 p) {
    vec3 o = p - f.root;
    return vec3(dot(o, f.across), o.y, dot(o, f.normal));
}

vec3 to_world(BladeFrame f, vec3 l) {
    return f.root + f.across * l.x + vec3(0.0, l.y, 0.0) + f.normal * l.z;
}

// The patch of `blade` at record `base` (`carried`: it holds the previous frame's step; `reach.x`: a
// collider reaches the blade, `reach.y`: a ground circle holds its root) a frame on:
// its chain stepped from the record, or at hand-in fitted to the cheap pose `cheap` (blade frame,
// every level); `local` becomes the chain's drawn curve blended towards `cheap`; where a collider
// reaches the blade the chain is held where the colliders push that (its joints from the first
// moved fitted to it, their angular velocities zeroed). The record is written, or freed once the
// patch has settled or blended back. Returns the chain's share of the drawn pose (0: freed).
float patch_step(uint base, bool carried, bvec2 reach, BladeInstance blade, uint blade_index, BladeFrame f,
                 uint segments, vec3 cheap[MAX_SEGMENTS + 1u], inout vec3 local[MAX_SEGMENTS + 1u]) {
    vec3 n[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), n);
    Chain chain = chain_of(n);
    ChainState s;
    float blend = 0.0;
    float idle = 0.0;
    // Loops of at most one turn for the branches: llvmpipe runs an untaken branch's body under a
    // mask, but leaves a loop no lane is in (push_out.comp says more).
    for (uint turn = carried ? 0u : 1u; turn < 1u; turn++) {
        patch_read(base, s);
        blend = uintBitsToFloat(patches[base + 3u]);
        idle = uintBitsToFloat(patches[base + 4u]);
        // The wind at the root in the blade's frame, the colliders' push with it (forces.glsl).
        vec2 wind = blade_force(blade_index, blade) * KEYFRAME_WIND_SCALE;
        vec3 w = vec3(dot(wind, f.across.xz), 0.0, dot(wind, f.normal.xz));
        for (uint step = 0u; step < patch_steps.y; step++) {
            chain_step(chain, s, w, patch_chain.yz, patch_chain.x);
        }
    }
    for (uint turn = carried ? 1u : 0u; turn < 1u; turn++) {
        chain_fit(chain, cheap, segments, 0u, s);
    }
    float elapsed = float(patch_steps.y) * patch_chain.x;
    idle = reach.x ? 0.0 : idle + elapsed;
    blend = idle < PATCH_TIMEOUT ? max(blend - elapsed / PATCH_BLEND, 0.0) : blend + elapsed / PATCH_BLEND;
    vec3 drawn[MAX_SEGMENTS + 1u];
    chain_points(chain, s, drawn);
    // Settled: every joint slow and every drawn point within a pixel of the cheap pose's.
    float pixel = distance(frame.camera_position.xyz, blade.position) / max(frame.cull_eye.w, 1e-6);
    float apart = 0.0;
    for (uint level = 1u; level <= MODEL_SEGMENTS; level++) {
        apart = max(apart, distance(drawn[level], cheap[level]));
    }
    float spin = 0.0;
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        spin = max(spin, length(s.omega[k]));
    }
    if (blend >= 1.0 || (!reach.x && carried && spin < PATCH_SETTLED && apart < pixel)) {
        // Handed back: the record is free, the cheap pose drawn.
        patches[base + 2u] = 0u;
        return 0.0;
    }
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        local[level] = mix(drawn[level], cheap[level], blend);
    }
    // Held where the colliders push it: only a blade whose root a ground circle holds is pushed.
    for (uint turn = reach.y ? 0u : 1u; turn < 1u; turn++) {
        vec3 held[MAX_SEGMENTS + 1u];
        for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
            held[level] = to_world(f, local[level]);
        }
        uint moved = push_out_colliders(held, colliders_near(f.root.xz));
        for (uint fit = moved <= MODEL_SEGMENTS ? 0u : 1u; fit < 1u; fit++) {
            for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
                held[level] = to_local(f, held[level]);
            }
            chain_fit(chain, held, MODEL_SEGMENTS, ((moved - 1u) * CHAIN_SEGMENTS) / MODEL_SEGMENTS, s);
        }
    }
    patch_write(base, s, blend, idle);
    // Renewed every frame it lives: it is freed by then.
    patch_lives_until(blade.position.xz, pressed_times.x + PATCH_TIMEOUT + PATCH_BLEND + 0.1);
    return 1.0 - blend;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= min(patch_list_head.w, PATCH_CAPACITY)) {
        return;
    }
    uvec4 listed = patch_list[i];
    uint record = listed.x;
    uvec2 entry = listed.yz;
    uint segments = listed.w & ~(PATCH_REACHED | PATCH_HELD);
    bool reach = (listed.w & PATCH_REACHED) != 0u;
    bool held = (listed.w & PATCH_HELD) != 0u;
    BladeInstance blade;
    uint blade_index = record;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        blade = visible_instance(entry, blade_index);
    } else {
        blade = blade_record(record);
    }
    BladeFrame f = BladeFrame(blade.position, vec3(cos(blade.facing), 0.0, -sin(blade.facing)),
                              vec3(sin(blade.facing), 0.0, cos(blade.facing)));
    // The cheap response's pose, in the blade's frame (metres), the unread levels on the line
    // between the read ones.
    float scale = POSE_SCALE * max(blade.height, 1e-6);
    uint pose = pose_base(record);
    vec3 cheap[MAX_SEGMENTS + 1u];
    vec2 twists[MAX_SEGMENTS + 1u];
    float forces[MAX_SEGMENTS + 1u];
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        vec3 unit = vec3(0.0);
        vec4 tangent_force = vec4(0.0);
        twists[level] = vec2(1.0, 0.0);
        if (level_read_in(segments, level)) {
            read_pose_level(pose, level, unit, twists[level], tangent_force);
        }
        cheap[level] = unit * scale;
        forces[level] = tangent_force.w;
    }
    for (uint level = 1u; level < MODEL_SEGMENTS; level++) {
        cheap[level] = level_read_in(segments, level) ? cheap[level] : backbone_at(cheap, segments, float(level) / float(MODEL_SEGMENTS));
    }
    vec3 local[MAX_SEGMENTS + 1u] = cheap;
    bool carried;
    uint base = patch_find(patch_key(entry, blade_index), reach, carried);
    float share = 0.0;
    for (uint turn = base != PATCH_NONE ? 0u : 1u; turn < 1u; turn++) {
        share = patch_step(base, carried, bvec2(reach, held), blade, blade_index, f, segments, cheap, local);
    }
    // The pressed map's bend and cut, then the colliders, as the push-out pass walks a blade.
    vec3 points[MAX_SEGMENTS + 1u];
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        points[level] = to_world(f, local[level]);
    }
    vec3 pressed = pressed_counts.y != 0u ? pressed_at(blade.position.xz) : vec3(0.0, 0.0, 1.0);
    if (pressed.z < 1.0 || dot(pressed.xy, pressed.xy) > 1e-10) {
        press_points(points, pressed);
    }
    // (push_out_points walks the levels level_read holds: every one, this pipeline's SEGMENTS being
    // MODEL_SEGMENTS.)
    push_out_colliders(points, colliders_near(blade.position.xz));
    // Every level the bucket reads, its tangent from the read levels either side; the debug views'
    // shares in the force channel.
    float inv = 1.0 / scale;
    uint below = 0u;
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read_in(segments, level)) {
            continue;
        }
        uint above = level;
        for (uint next = MODEL_SEGMENTS; next > level; next--) {
            above = level_read_in(segments, next) ? next : above;
        }
        vec3 t = points[above] - points[below];
        t = length(t) > 0.0 ? normalize(t) : vec3(0.0, 1.0, 0.0);
        float shown = forces[level];
        if ((RENDER_FLAGS & FLAG_DEBUG_PRESSED) != 0u) {
            shown = max(length(pressed.xy), (1.0 - pressed.z) / (1.0 - PRESSED_STUB));
        }
        if ((RENDER_FLAGS & FLAG_DEBUG_PATCHES) != 0u) {
            shown = share;
        }
        vec3 tangent = vec3(dot(t, f.across), t.y, dot(t, f.normal));
        write_pose_level(pose, level, to_local(f, points[level]) * inv, tangent, twists[level], shown);
        below = level;
    }
}
