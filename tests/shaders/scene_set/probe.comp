#version 460
#extension GL_GOOGLE_include_directive : require
// tests/scene_set.rs: a shader of set 0 that reads one of the library's resources (`Corners`,
// animation/frame_forces.glsl) and writes one of its own (`ProbeWords`, probe_words.glsl), both numbered
// by build.rs, both given by name.
#include "animation/frame_forces.glsl"
#include "probe_words.glsl"

layout(local_size_x = 1) in;

void main() {
    probe_words[0] = SCENE_BINDING_ProbeWords;
    probe_words[1] = SCENE_BINDING_Corners;
    probe_words[2] = floatBitsToUint(corners[0].y);
}
