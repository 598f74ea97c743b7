#version 460
#extension GL_GOOGLE_include_directive : require
// `--eval blade`: the per-blade half of the animation — force interpolation (eq. 3.6), delayed
// attenuation (4.5), the blade frame and the keyframe selection (eq. 3.10–3.12) — done once per
// blade instead of once per vertex, written as a 16-byte pose record blade.vert reads. The
// thesis' chapter 7 future work, with a compute pass.
#define POSE_WRITER
#include "bindings.glsl"
#include "forces.glsl"
#include "keyframes.glsl"
#include "blade_select.glsl"

layout(local_size_x = 64) in;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= frame.params.y) {
        return;
    }
    float force;
    KfSelection s = kf_select_blade(i, blades[i], force);
    poses[i] = kf_pack(s, force);
}
