#version 460
#extension GL_GOOGLE_include_directive : require
// Belyaev's virtual blades (§3.3), the first pass of the virtually-inertial response
// (`render::animation::virtual_blades`): at every wind corner (the centres of the wind's texels,
// every level of a block field's), an upright virtual blade of VIRTUAL_HEIGHT is stepped with the
// inertial chain (animation/chain.glsl: §3.1's simplified algorithm under §3.2's drag) under the
// corner's wind, and its virtual moments mₖ = k·ψₖ (gravity left out, as in the inertial blades)
// are written to the virtual wind, one vec4 per joint, as the force per unit mass whose moment on
// the virtual segment they are (`chain_virtual_forces`). The drawn blades take their static
// equilibrium under it (animation/virtual_inertial.comp): no state per drawn blade.
//
// The virtual blades' state (ψ, ω per joint, 24 floats a corner) is a ping-pong pair: this pass
// reads the side the last submitted frame wrote and writes the other. A block field's corners
// move with O: a corner reads the state of the corner that was at its world position last frame
// (O's move in `control.motion`, rounded to the nearest corner of its level), and a corner that
// entered its level (or every corner, on a restart) starts at the equilibrium under this frame's
// wind. Its own set (no scene sets). Mirrored on the CPU by `render::animation::chain::Chain`
// (`upright`, `step`, `equilibrium`, `virtual_forces`).
#include "common/shared.glsl"
#include "animation/chain.glsl"

layout(local_size_x = WIND_GROUP) in;

// `render::animation::virtual_blades::VirtualFrame`, one block bound twice: as a uniform block
// for the arithmetic, through a storage binding for what decides control flow (the lavapipe
// profile's rule, common/profile.glsl).
#define VIRTUAL_PARAMS \
    uvec4 counts;  /* corners of the levels stepped (innermost first), corners per side of a level, 1: restart every blade, steps to take */ \
    vec4 motion;   /* O's move since the last frame (x, z, m), the step (s), 0 */ \
    vec4 chain;    /* k/J (1/s²), d/J (1/s), the virtual blade's height (m), 0 */ \
    vec4 levels[WIND_LEVELS]; /* per level: first corner relative to O (x, z), spacing, 0 */
layout(set = 0, binding = 0, std140) uniform VirtualValues { VIRTUAL_PARAMS } values;
layout(set = 0, binding = 1, std430) readonly buffer VirtualControl { VIRTUAL_PARAMS } control;
// This frame's wind at the corners: velocity (x, y, z) in m/s, exposure.
layout(set = 0, binding = 2, std430) readonly buffer Corners { vec4 corners[]; };
layout(set = 0, binding = 3, std430) readonly buffer VirtualPrevious { float previous[]; };
layout(set = 0, binding = 4, std430) writeonly buffer VirtualCurrent { float current[]; };
// Per corner, per joint: the virtual moment as a force per unit mass (x, y, z), 0.
layout(set = 0, binding = 5, std430) writeonly buffer VirtualWind { vec4 virtual_wind[]; };

const uint VIRTUAL_STATE_FLOATS = 6u * CHAIN_SEGMENTS; // render::animation::virtual_blades::STATE_FLOATS

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= control.counts.x) {
        return;
    }
    uint n = control.counts.y;
    uint level = c / (n * n);
    uint local = c % (n * n);
    vec4 lv = control.levels[level];
    vec2 here = lv.xy + vec2(uvec2(local % n, local / n)) * lv.z;
    vec4 corner = corners[c];
    vec3 w = vec3(corner.x, 0.0, corner.z);
    float h = values.chain.z;
    vec3 upright[4] = vec3[4](vec3(0.0), vec3(0.0, h / 3.0, 0.0), vec3(0.0, 2.0 * h / 3.0, 0.0), vec3(0.0, h, 0.0));
    Chain chain = chain_of(upright);
    // The corner at this world position last frame, in last frame's window of the level.
    vec2 g = floor((here + control.motion.xy - lv.xy) / lv.z + 0.5);
    bool carried = control.counts.z == 0u && all(greaterThanEqual(g, vec2(0.0))) && all(lessThan(g, vec2(float(n))));
    ChainState s;
    if (carried) {
        uint from = (level * n * n + uint(g.y) * n + uint(g.x)) * VIRTUAL_STATE_FLOATS;
        for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
            uint at = from + 6u * k;
            s.psi[k] = vec3(previous[at], previous[at + 1u], previous[at + 2u]);
            s.omega[k] = vec3(previous[at + 3u], previous[at + 4u], previous[at + 5u]);
        }
        for (uint step = 0u; step < control.counts.w; step++) {
            chain_step(chain, s, w, values.chain.xy, values.motion.z);
        }
    } else {
        s = chain_equilibrium(chain, w, values.chain.x);
    }
    uint to = c * VIRTUAL_STATE_FLOATS;
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        uint at = to + 6u * k;
        current[at] = s.psi[k].x;
        current[at + 1u] = s.psi[k].y;
        current[at + 2u] = s.psi[k].z;
        current[at + 3u] = s.omega[k].x;
        current[at + 4u] = s.omega[k].y;
        current[at + 5u] = s.omega[k].z;
    }
    vec3 f[CHAIN_SEGMENTS];
    chain_virtual_forces(chain, s, values.chain.x, f);
    for (uint k = 0u; k < CHAIN_SEGMENTS; k++) {
        virtual_wind[c * CHAIN_SEGMENTS + k] = vec4(f[k], 0.0);
    }
}
