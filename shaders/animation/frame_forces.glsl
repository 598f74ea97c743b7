// Set 0: this frame's forces, owned by `render::wind::frame_forces::FrameForces` (one pair per
// frame in flight, given by name, `render::wind::frame_forces::FrameForces::scene_resources`).
#ifndef MEADOW_FRAME_FORCES_GLSL
#define MEADOW_FRAME_FORCES_GLSL
#include "common/profile.glsl"

// Per frame: forces at cluster corners (xy force, z calm-area exposure), and point sources
// (x, z, power, sigma) followed by colliders (centre x, z, radius x, z).
layout(SCENE(Corners), std430) readonly buffer Corners { vec4 corners[]; };
layout(SCENE(Emitters), std430) readonly buffer Emitters { vec4 emitters[]; };

#endif
