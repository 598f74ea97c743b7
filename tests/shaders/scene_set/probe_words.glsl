// A set-0 resource only the tests declare (tests/scene_set.rs): its binding comes from build.rs,
// which numbers the tests' names after the library's, and the test gives it by this name.
#ifndef MEADOW_PROBE_WORDS_GLSL
#define MEADOW_PROBE_WORDS_GLSL
#include "common/profile.glsl"

layout(SCENE(ProbeWords), std430) writeonly buffer ProbeWords { uint probe_words[]; };

#endif
