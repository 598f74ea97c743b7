// Writing a segment chain's drawn curve to a blade's pose records, at the levels its LOD bucket
// reads: what the inertial (`animation/inertial.comp`) and the virtually-inertial
// (`animation/virtual_inertial.comp`) pose passes share. The includer has included
// animation/pose_write.glsl and animation/chain.glsl.
#ifndef MEADOW_CHAIN_POSE_GLSL
#define MEADOW_CHAIN_POSE_GLSL

// The curve with controls p (blade frame, root at 0) of a blade of `height` whose neutral tip is
// `neutral_tip`, its segments' frames `frames` (the width turns with them: a level takes its
// segment's across axis, projected onto the ground), into the records at `base`.
void write_chain_pose(uint base, float height, vec3 neutral_tip, vec3 p[3], vec4 frames[CHAIN_SEGMENTS]) {
    float inv = 1.0 / (POSE_SCALE * max(height, 1e-6));
    float force = length(p[2] - neutral_tip) / max(height, 1e-6);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read(level)) {
            continue;
        }
        float t = float(level) / float(MODEL_SEGMENTS);
        vec3 point = bezier_point(vec3(0.0), p[0], p[1], p[2], t);
        vec3 tangent = bezier_tangent(vec3(0.0), p[0], p[1], p[2], t);
        tangent = length(tangent) > 0.0 ? normalize(tangent) : vec3(0.0, 1.0, 0.0);
        // (cos, sin) of the turn about +y (blade_place.glsl: width = across·cos − normal·sin).
        vec3 width = quat_rotate(frames[min(uint(t * float(CHAIN_SEGMENTS)), CHAIN_SEGMENTS - 1u)], vec3(1.0, 0.0, 0.0));
        vec2 turn = length(width.xz) > 1e-6 ? normalize(vec2(width.x, -width.z)) : vec2(1.0, 0.0);
        write_pose_level(base, level, point * inv, tangent, turn, force);
    }
}

#endif
