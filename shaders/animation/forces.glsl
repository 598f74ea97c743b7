// The keyframes' input (thesis 3.2.2, 4.5): the force a blade's pose is selected by, the wind
// field's velocity at the blade (`wind/wind_field.glsl`) mapped back to keyframe units by the
// fixed scale `wind::KEYFRAME_WIND_SCALE` (|f| = 1, the table's strongest pose, is 8 m/s; a
// power of two, so the mapping is exact). Mirrors `render::animation::blade_force` on the CPU.
#ifndef MEADOW_FORCES_GLSL
#define MEADOW_FORCES_GLSL
#include "wind/wind_field.glsl"

vec2 blade_force(uint blade_index, vec2 root) {
    return wind_at_blade(blade_index, root).xz * (1.0 / KEYFRAME_WIND_SCALE);
}

#endif
