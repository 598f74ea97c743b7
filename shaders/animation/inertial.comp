#version 460
#extension GL_GOOGLE_include_directive : require
// Belyaev's inertial blades (§3.1), a stateful blade response (`render::animation::inertial`):
// each drawn blade's segment chain (animation/chain.glsl gives the model, the equations and
// meadow's choices) is stepped in the blade-state store (animation/blade_state.glsl), up to 4
// steps a frame, and its drawn curve written to the pose records at the levels the blade's LOD
// bucket reads. A blade whose record does not carry on restarts at the static equilibrium under
// this frame's wind; past the store it draws that equilibrium, blended in across the store's
// outermost ring.
#define POSE_WRITER
#include "common/bindings.glsl"
#include "animation/forces.glsl"
#include "animation/pose_write.glsl"
#include "animation/blade_state.glsl"
#include "animation/chain.glsl"
#include "animation/chain_pose.glsl"

layout(local_size_x = POSE_GROUP) in;

// The response's constants (`render::animation::chain::ChainParams`), in its pass's own set.
layout(set = SET_PASS, binding = 1, std140) uniform InertialShape {
    vec4 inertial; // x k/J, the joints' stiffness (1/s²); y d/J, their damper (1/s); zw unused
};

// STATE_WORDS = 6 · CHAIN_SEGMENTS (render::animation::inertial::STATE_WORDS): ψ, then ω, per joint.
void read_chain(BladeState s, out ChainState c) {
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        uint at = 6u * k;
        c.psi[k] = uintBitsToFloat(uvec3(state_word(s, at), state_word(s, at + 1u), state_word(s, at + 2u)));
        c.omega[k] = uintBitsToFloat(uvec3(state_word(s, at + 3u), state_word(s, at + 4u), state_word(s, at + 5u)));
    }
}

void write_chain(BladeState s, ChainState c) {
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        uint at = 6u * k;
        uvec3 psi = floatBitsToUint(c.psi[k]);
        uvec3 omega = floatBitsToUint(c.omega[k]);
        set_state_word(s, at, psi.x);
        set_state_word(s, at + 1u, psi.y);
        set_state_word(s, at + 2u, psi.z);
        set_state_word(s, at + 3u, omega.x);
        set_state_word(s, at + 4u, omega.y);
        set_state_word(s, at + 5u, omega.z);
    }
    state_written(s);
}

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
    vec2 normal_dir = vec2(sin(blade.facing), cos(blade.facing));
    // The wind at the root in the blade's frame.
    vec2 wind = blade_force(blade_index, blade) * KEYFRAME_WIND_SCALE;
    vec3 w = vec3(dot(wind, across), 0.0, dot(wind, normal_dir));
    vec3 n[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), n);
    Chain chain = chain_of(n);
    BladeState s = blade_state(entry, blade_index);
    bool carried = s.base != STATE_NONE && s.carried;
    ChainState still;
    if (!carried || s.stateless > 0.0) {
        still = chain_equilibrium(chain, w, inertial.x);
    }
    ChainState state;
    if (carried) {
        read_chain(s, state);
        for (uint step = 0u; step < state_steps_to_take(); step++) {
            chain_step(chain, state, w, inertial.xy, state_time.x);
        }
    } else {
        state = still;
    }
    if (s.base != STATE_NONE) {
        write_chain(s, state);
    }
    vec4 frames[CHAIN_SEGMENTS];
    chain_frames(chain, state, frames);
    vec3 p[3];
    chain_controls(chain, frames, p);
    if (s.stateless > 0.0) {
        vec4 still_frames[CHAIN_SEGMENTS];
        chain_frames(chain, still, still_frames);
        vec3 q[3];
        chain_controls(chain, still_frames, q);
        for (uint k = 0u; k < 3u; k++) {
            p[k] = mix(p[k], q[k], s.stateless);
        }
        if (s.stateless >= 0.5) {
            frames = still_frames;
        }
    }
    write_chain_pose(pose_base(i), blade.height, n[3], p, frames);
}
