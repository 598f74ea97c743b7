// The keyframes' input (thesis 3.2.2, 4.5, 5.2): the force a blade's pose is selected by. The
// wind field's velocity at the blade (`wind/wind_field.glsl`) mapped back to keyframe units by the
// fixed scale `wind::KEYFRAME_WIND_SCALE` (|f| = 1, the table's strongest pose, is 8 m/s; a power
// of two, so the mapping is exact), plus every collider's reach-weighted force (`docs/animation.md`,
// "Colliders in 3-D", eq. C.1–C.3). Mirrors `render::animation::blade_force` on the CPU.
#ifndef MEADOW_FORCES_GLSL
#define MEADOW_FORCES_GLSL
#include "wind/wind_field.glsl"
#include "animation/collider_bins.glsl"

const float COLLIDER_PUSH = 1.2; // wind::COLLIDER_PUSH: the force on a blade wholly inside

// The reach-weighted force of the ellipsoid at `center` (x, z relative to O, y a world height)
// with `radii` on a blade rooted at `root` (the same frame) with backbone length `height`: the
// part [s0, s1] of the upright backbone inside it (eq. C.1: the vertical line through the root
// meets it over center.y ± radii.y √(1 − q · q)), pushed along the ellipse's outward normal with
// density COLLIDER_PUSH / h; its moment about the root over the moment arm h / 2 of a uniform load
// (eq. C.3): COLLIDER_PUSH · n · (s1² − s0²) / h². Zero for a blade that does not reach into it.
// Mirrors `wind::Collider::blade_force`.
vec2 collider_force(vec3 center, vec3 radii, vec3 root, float height) {
    vec2 q = (root.xz - center.xz) / radii.xz;
    float d2 = dot(q, q);
    if (d2 >= 1.0 || d2 < 1e-12 || height <= 0.0) {
        return vec2(0.0);
    }
    float half_height = radii.y * sqrt(1.0 - d2);
    float s0 = clamp(center.y - half_height - root.y, 0.0, height);
    float s1 = clamp(center.y + half_height - root.y, 0.0, height);
    if (s1 <= s0) {
        return vec2(0.0);
    }
    vec2 n = normalize(q / radii.xz);
    return n * (COLLIDER_PUSH * (s1 * s1 - s0 * s0) / (height * height));
}

// `force` with the colliders' push on an upright of `height` m at `root` added: two emitters
// each (centre, radii) after the sources, under either attenuation. Added only where they push,
// so a blade no collider reaches keeps its force to the bit (-0 + 0 would be +0). Only the
// colliders whose ground ellipse may hold the root (animation/collider_bins.glsl), in ascending
// order as all of them were. The far plants' lean reads it too (far_field/far.vert).
vec2 add_collider_push_at(vec2 force, vec3 root, float height) {
    uint first = frame.wind_counts.x;
    uvec4 near = colliders_near(root.xz);
    while (near != uvec4(0u)) {
        uint e = first + 2u * next_collider(near);
        vec2 push = collider_force(emitters[e].xyz, emitters[e + 1u].xyz, root, height);
        if (push != vec2(0.0)) {
            force += push;
        }
    }
    return force;
}

// The same for a blade: at its root, over its backbone's length.
vec2 add_collider_push(vec2 force, BladeInstance blade) {
    return add_collider_push_at(force, blade.position, blade.height);
}

vec2 blade_force(uint blade_index, BladeInstance blade) {
    return add_collider_push(wind_at_blade(blade_index, blade.position.xz).xz * (1.0 / KEYFRAME_WIND_SCALE), blade);
}

#endif
