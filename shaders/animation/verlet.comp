#version 460
#extension GL_GOOGLE_include_directive : require
// Zhang Xia's Verlet blades (§3.2.3–3.2.5), a stateful blade response
// (`render::animation::verlet`, mirrored on the CPU by `render::animation::verlet::VerletBlade`).
// A blade is its cubic Bézier backbone (eq. 5): the root P0 fixed, the control points P1..P3 integrated with Verlet (eq. 7),
//   x' = 2x − x'' + a·Δt²,  x'' = x,
// under the acceleration
//   a = k_a·(w − v) + k_s·(r − x),  v = (x − x'') / Δt,
// a linear drag towards the wind w (m/s at the root: the wind field's plus the colliders' push as
// a local wind, thesis 5.2) and, meadow's addition, a spring towards the rest shape r (Zhang Xia's
// blade has none: without it a blade would not stand up again). Gravity is left out: with a linear
// spring a constant gravity only moves the spring's rest target, and that target must be the
// neutral blade for a blade under no wind to rest at it. After each step:
//   - y = |y| (Zhang Xia's `abs`), so no point goes below the root;
//   - the length constraint of §3.2.4, bottom to top: each segment P(i−1)P(i) of the control
//     polygon is put back to its rest length along its own direction;
//   - the drawn curve's arc length, measured over ARC_SAMPLES chords, is scaled back to the rest
//     curve's by scaling P1..P3 about the root (a uniform scale scales the curve's length by the
//     same factor; the polygon constraint alone lets the curve shorten as the polygon bends).
// The width turns towards the wind (§3.2.5): level m of M turns by θ·m/M, θ the turn that sets the
// width perpendicular to the lean (the root-to-tip direction), the smaller of the two ways.
// The state is P1..P3 and their previous positions (world axes, relative to the root, metres) in
// the blade-state store (animation/blade_state.glsl). A blade whose record does not carry on
// restarts at the equilibrium under this frame's wind, x = r + (k_a / k_s)·w constrained and at
// rest; past the store it draws that equilibrium, blended in across the store's outermost ring.
#define POSE_WRITER
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "animation/forces.glsl"
#include "animation/pose_write.glsl"
#include "animation/blade_state.glsl"

layout(local_size_x = POSE_GROUP) in;

// The response's constants (`render::animation::verlet::VerletParams`), in its pass's own set.
layout(set = SET_PASS, binding = 1, std140) uniform VerletShape {
    vec4 verlet; // x k_s, the stiffness (1/s²); y k_a, the drag rate (1/s); zw unused
};

const uint ARC_SAMPLES = 8u; // render::animation::verlet::ARC_SAMPLES
const uint STATE_WORDS = 18u; // render::animation::verlet::STATE_WORDS: P1..P3, then their previous positions

// The length of the Bézier curve from the root through `p` over ARC_SAMPLES chords.
float arc_length(vec3 p[3]) {
    float length_sum = 0.0;
    vec3 before = vec3(0.0);
    for (uint k = 1u; k <= ARC_SAMPLES; k++) {
        vec3 at = bezier_point(vec3(0.0), p[0], p[1], p[2], float(k) / float(ARC_SAMPLES));
        length_sum += length(at - before);
        before = at;
    }
    return length_sum;
}

// The constraints of a step: the ground, the polygon's rest lengths (§3.2.4), the curve's length.
void constrain(inout vec3 p[3], vec3 rest[3], float rest_arc) {
    vec3 below = vec3(0.0);
    vec3 rest_below = vec3(0.0);
    for (uint i = 0u; i < 3u; i++) {
        p[i].y = abs(p[i].y);
        vec3 d = p[i] - below;
        float len = length(d);
        float l = length(rest[i] - rest_below);
        p[i] = len > 1e-6 ? below + d * (l / len) : rest[i];
        below = p[i];
        rest_below = rest[i];
    }
    float scale = rest_arc / max(arc_length(p), 1e-6);
    for (uint i = 0u; i < 3u; i++) {
        p[i] *= scale;
    }
}

vec3 state_point(BladeState s, uint at) {
    return vec3(uintBitsToFloat(state_word(s, at)), uintBitsToFloat(state_word(s, at + 1u)),
        uintBitsToFloat(state_word(s, at + 2u)));
}

void set_state_point(BladeState s, uint at, vec3 p) {
    set_state_word(s, at, floatBitsToUint(p.x));
    set_state_word(s, at + 1u, floatBitsToUint(p.y));
    set_state_word(s, at + 2u, floatBitsToUint(p.z));
}

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    vec2 wind = blade_force(blade_index, blade) * KEYFRAME_WIND_SCALE;
    vec3 w = vec3(wind.x, 0.0, wind.y);
    vec3 n[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), n);
    vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
    vec2 normal_dir = vec2(sin(blade.facing), cos(blade.facing));
    // The rest shape in world axes, relative to the root.
    vec3 rest[3];
    for (uint k = 0u; k < 3u; k++) {
        vec2 h = across * n[k + 1u].x + normal_dir * n[k + 1u].z;
        rest[k] = vec3(h.x, n[k + 1u].y, h.y);
    }
    float rest_arc = arc_length(rest);
    float ks = verlet.x;
    float ka = verlet.y;
    BladeState s = blade_state(entry, blade_index);
    bool carried = s.base != STATE_NONE && s.carried;
    // The equilibrium under this frame's wind: the start of a restart, and the stateless shape
    // (only made where it is used: most drawn blades carry on, inside the store).
    vec3 still[3];
    if (!carried || s.stateless > 0.0) {
        for (uint k = 0u; k < 3u; k++) {
            still[k] = rest[k] + (ka / ks) * w;
        }
        constrain(still, rest, rest_arc);
    }
    vec3 x[3];
    vec3 previous[3];
    if (carried) {
        for (uint k = 0u; k < 3u; k++) {
            x[k] = state_point(s, 3u * k);
            previous[k] = state_point(s, 9u + 3u * k);
        }
        float dt = state_time.x;
        for (uint step = 0u; step < state_steps_to_take(); step++) {
            for (uint k = 0u; k < 3u; k++) {
                vec3 v = (x[k] - previous[k]) / dt;
                vec3 a = ka * (w - v) + ks * (rest[k] - x[k]);
                vec3 next = 2.0 * x[k] - previous[k] + a * (dt * dt);
                previous[k] = x[k];
                x[k] = next;
            }
            constrain(x, rest, rest_arc);
        }
    } else {
        x = still;
        previous = still;
    }
    if (s.base != STATE_NONE) {
        for (uint k = 0u; k < 3u; k++) {
            set_state_point(s, 3u * k, x[k]);
            set_state_point(s, 9u + 3u * k, previous[k]);
        }
        state_written(s);
    }
    if (s.stateless > 0.0) {
        for (uint k = 0u; k < 3u; k++) {
            x[k] = mix(x[k], still[k], s.stateless);
        }
    }
    // §3.2.5: the turn that sets the width perpendicular to the lean, the smaller way.
    vec2 lean = x[2].xz;
    float theta = 0.0;
    if (length(lean) > 1e-4 * blade.height) {
        theta = atan(dot(across, lean), dot(normal_dir, lean));
        theta -= theta > 0.5 * PI ? PI : (theta < -0.5 * PI ? -PI : 0.0);
    }
    float inv = 1.0 / (POSE_SCALE * max(blade.height, 1e-6));
    float force = length(x[2] - rest[2]) / max(blade.height, 1e-6);
    uint base = pose_base(i);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read(level)) {
            continue;
        }
        float t = float(level) / float(MODEL_SEGMENTS);
        vec3 point = bezier_point(vec3(0.0), x[0], x[1], x[2], t);
        vec3 tangent = bezier_tangent(vec3(0.0), x[0], x[1], x[2], t);
        // Into the blade's frame (x across, y up, z along the normal).
        vec3 local = vec3(dot(point.xz, across), point.y, dot(point.xz, normal_dir));
        vec3 local_tangent = vec3(dot(tangent.xz, across), tangent.y, dot(tangent.xz, normal_dir));
        local_tangent = length(local_tangent) > 0.0 ? normalize(local_tangent) : vec3(0.0, 1.0, 0.0);
        float turn = theta * t;
        write_pose_level(base, level, local * inv, local_tangent, vec2(cos(turn), sin(turn)), force);
    }
}
