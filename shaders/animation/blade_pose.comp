#version 460
#extension GL_GOOGLE_include_directive : require
// `--eval blade`: the per-blade half of the animation — force interpolation (eq. 3.6), delayed
// attenuation (4.5), the blade frame, the keyframe selection (eq. 3.10–3.12) and the blend of
// every chain level (eq. 3.13/3.14) — done once per blade instead of once per vertex (three
// times per vertex, for the tangent). The evaluated levels go to the pose records (bindings.glsl):
// blade.vert reads them without the cull; with it, blade_levels.comp places and lights them for
// the drawn blades. The thesis' chapter 7 future work, with a compute pass. With the cull, it runs
// after it over the drawn blades only, one dispatch per LOD bucket (visible_buckets.glsl), and
// writes only the levels the bucket reads: a store is a loop over the SIMD lanes on llvmpipe, and
// at the unbounded field's default view three blades in four draw one segment (2 of 5 levels).
#define POSE_WRITER
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "animation/forces.glsl"
#include "animation/keyframes.glsl"
#include "blades/blade_select.glsl"
#include "animation/pose_write.glsl"

// With the cull (FLAG_CULLED): one invocation per entry of a LOD bucket's range of its visible
// list, dispatched indirectly by the scan's count, records by entry; without it, one per stored
// blade, every level.
layout(local_size_x = POSE_GROUP) in;

// Model level `level`'s record: the level's point over the blade's scaled height, its twist, its
// tangent (from the neighbouring levels' points) and the force.
void write_level(uint base, uint level, vec4 points[MAX_SEGMENTS + 1u], float inv, float force) {
    vec3 tangent = points[min(level + 1u, MODEL_SEGMENTS)].xyz - points[level > 0u ? level - 1u : 0u].xyz;
    tangent = length(tangent) > 0.0 ? normalize(tangent) : vec3(0.0, 1.0, 0.0);
    float twist = points[level].w;
    write_pose_level(base, level, points[level].xyz * inv, tangent, vec2(cos(twist), sin(twist)), force);
}

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    float force;
    KfSelection sel = kf_select_blade(blade_index, blade, force);
    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    uint base = pose_base(i);
    vec4 c1;
    vec4 c2;
    vec4 c3;
    if (REPRESENTATION == REPRESENTATION_CURVE) {
        curve_controls(sel, p, blade.height, c1, c2, c3);
    }
    // Points of every level first (the tangent of a level needs its neighbours).
    vec4 points[MAX_SEGMENTS + 1u];
    points[0] = vec4(0.0);
    for (uint level = 1u; level <= MODEL_SEGMENTS; level++) {
        float t = float(level) / float(MODEL_SEGMENTS);
        points[level] = REPRESENTATION == REPRESENTATION_CURVE
            ? vec4(bezier_point(p[0], c1.xyz, c2.xyz, c3.xyz, t), c1.w * t)
            : deformed(p, sel, level, MODEL_SEGMENTS, blade.height);
    }
    float inv = 1.0 / (POSE_SCALE * max(blade.height, 1e-6));
    // Only the model levels the bucket's strip reads (`level_read`). A level indexed by a value
    // varying across lanes instead (a loop to the entry's own segments) made `points` a per-lane
    // array in memory on llvmpipe, and the pass took 2.3 times as long.
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (level_read(level)) {
            write_level(base, level, points, inv, force);
        }
    }
}
