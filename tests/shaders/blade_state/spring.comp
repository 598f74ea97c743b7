#version 460
#extension GL_GOOGLE_include_directive : require
// tests/blade_state.rs: a stateful blade response outside the library. Each drawn blade's tip
// offset (x, z, world frame, in blade heights) and its velocity are state in the blade-state
// store (animation/blade_state.glsl), stepped with semi-implicit Euler towards the offset the
// wind asks for:
//   target = clamp(GAIN · wind.xz),  a = K (target − x) − C v,  v += a dt,  x += v dt.
// A blade whose record does not carry on restarts at the equilibrium x = target, v = 0; past
// the store it draws that equilibrium (its stateless counterpart), blended in across the
// store's outermost ring of blocks. Its pose records bend the blade along a parabola to the tip.
#define POSE_WRITER
#include "common/bindings.glsl"
#include "wind/wind_field.glsl"
#include "animation/pose_write.glsl"
#include "animation/blade_state.glsl"

layout(local_size_x = POSE_GROUP) in;

const float GAIN = 0.08;      // heights per m/s
const float MOST = 0.6;       // heights
const float K = 40.0;         // 1/s², natural period 2π/√K ≈ 0.99 s
const float C = 3.0;          // 1/s

vec2 target_offset(vec2 wind) {
    vec2 t = wind * GAIN;
    float reach = length(t);
    return reach > MOST ? t * (MOST / reach) : t;
}

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    // The wind rounded to 1/1024 m/s: the interpolation's last-bit differences between camera
    // origins (the corners' weights change with O) do not reach the state, so a blade's state
    // across camera moves can be compared to the bit.
    vec2 wind = round(wind_at_blade(blade_index, blade.position.xz).xz * 1024.0) / 1024.0;
    vec2 target = target_offset(wind);
    BladeState s = blade_state(entry, blade_index);
    vec2 x = target;
    vec2 v = vec2(0.0);
    if (s.base != STATE_NONE) {
        if (s.carried) {
            x = vec2(uintBitsToFloat(state_word(s, 0u)), uintBitsToFloat(state_word(s, 1u)));
            v = vec2(uintBitsToFloat(state_word(s, 2u)), uintBitsToFloat(state_word(s, 3u)));
            float dt = state_time.x;
            for (uint k = 0u; k < state_steps_to_take(); k++) {
                vec2 a = K * (target - x) - C * v;
                v += a * dt;
                x += v * dt;
            }
        }
        set_state_word(s, 0u, floatBitsToUint(x.x));
        set_state_word(s, 1u, floatBitsToUint(x.y));
        set_state_word(s, 2u, floatBitsToUint(v.x));
        set_state_word(s, 3u, floatBitsToUint(v.y));
        // Not state: the weight of the stateless counterpart it was drawn with, for the test.
        set_state_word(s, 4u, floatBitsToUint(s.stateless));
        state_written(s);
    }
    vec2 offset = mix(x, target, s.stateless);
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
