// Push-out (Zhang Xia §6.2, "Sphere-plant Interaction"): a blade whose root lies inside a
// collider's ground circle (step 2) is walked from its root to its tip; the first backbone point
// inside the collider is moved out onto its surface (step 3), and the segments above it follow
// the direction from the point below to the moved one (step 4), so the blade lies along the
// collider where it touches it. meadow keeps every segment's length and stays outside where that
// direction would enter again: a point found inside is put on the collider's surface at its
// segment's length from the point below, the nearest such point to where the surface lies
// straight out from the collider's centre. An ellipsoid is worked in the space where it is the
// unit sphere (exact for a sphere; an ellipsoid's segments keep their length to within its
// aspect). The CPU mirror is `render::animation::push_out::push_out`.
#ifndef MEADOW_PUSH_OUT_GLSL
#define MEADOW_PUSH_OUT_GLSL
#include "animation/collider_bins.glsl"

// Whether `p` lies inside the unit sphere: `p` in the collider's unit space.
bool unit_inside(vec3 p) {
    return dot(p, p) < 1.0;
}

// The point at distance `len` from `a` on the unit sphere nearest its point straight out through
// `q` (all in the collider's unit space, centre at 0). `a` outside or on it: the sphere of radius `len`
// round `a` meets the unit sphere in a circle (q inside and |q − a| = len make sure it does); the
// point of that circle towards q's radial point. `a` inside (a root under the collider's
// surface): a segment's length straight out from the centre through q.
vec3 unit_surface_from(vec3 a, vec3 q, float len) {
    vec3 radial = length(q) > 1e-6 ? normalize(q) : vec3(0.0, 1.0, 0.0);
    float d = length(a);
    // On the surface (a point moved before) counts as outside.
    if (d < 1.0 - 1e-4) {
        return a + len * radial;
    }
    vec3 u = -a / d;
    // The circle's plane lies h from a along u, its radius rho.
    float h = (d * d + len * len - 1.0) / (2.0 * d);
    float rho = sqrt(max(len * len - h * h, 0.0));
    vec3 towards = radial - a;
    vec3 v = towards - dot(towards, u) * u;
    if (dot(v, v) < 1e-12) {
        // q's radial point straight beyond a (a root under the centre): any way across.
        v = abs(u.x) < 0.9 ? cross(u, vec3(1.0, 0.0, 0.0)) : cross(u, vec3(0.0, 0.0, 1.0));
    }
    return a + h * u + rho * normalize(v);
}

// Push the backbone `points` (world positions relative to the origin, levels 0..MODEL_SEGMENTS;
// only those `level_read` holds are walked) out of the ellipsoid at `center` with `radii`, whose
// ground circle holds the root points[0]. True if a point moved. `moved` gets the first moved level.
bool push_out_points(inout vec3 points[MAX_SEGMENTS + 1u], vec3 center, vec3 radii, out uint moved) {
    moved = MODEL_SEGMENTS + 1u;
    vec3 below = (points[0] - center) / radii;
    vec3 below_was = below;
    vec3 along = vec3(0.0);
    for (uint level = 1u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read(level)) {
            continue;
        }
        vec3 was = (points[level] - center) / radii;
        // Before the first push, the point stays; after it, Zhang Xia's step 4.
        vec3 q = moved > MODEL_SEGMENTS ? was : below + along * length(was - below_was);
        if (unit_inside(q)) {
            q = unit_surface_from(below, q, length(was - below_was));
            along = normalize(q - below);
            moved = min(moved, level);
        }
        below_was = was;
        below = q;
        if (moved <= MODEL_SEGMENTS) {
            points[level] = center + q * radii;
        }
    }
    return moved <= MODEL_SEGMENTS;
}

// Whether the ground circle of the collider at emitter `e` holds `root` (Zhang Xia's step 2;
// `render::animation::push_out::circle_holds`).
bool circle_holds(uint e, vec3 root) {
    vec2 q = (root.xz - emitters[e].xz) / emitters[e + 1u].xz;
    return dot(q, q) < 1.0;
}

// `points` (world, the root first) walked out of every collider of `near`
// (animation/collider_bins.glsl) whose ground circle holds the root, in ascending order: the first
// level moved (MODEL_SEGMENTS + 1: none).
uint push_out_colliders(inout vec3 points[MAX_SEGMENTS + 1u], uvec4 near) {
    uint first = frame.wind_counts.x;
    uint moved = MODEL_SEGMENTS + 1u;
    while (near != uvec4(0u)) {
        uint e = first + 2u * next_collider(near);
        uint from;
        if (circle_holds(e, points[0]) && push_out_points(points, emitters[e].xyz, emitters[e + 1u].xyz, from)) {
            moved = min(moved, from);
        }
    }
    return moved;
}

#endif
