#version 460
#extension GL_GOOGLE_include_directive : require
// Blade shading with `--msaa` and alpha to coverage: the outline's coverage per sample becomes the
// fragment's sample mask (blade_shading.glsl, SAMPLE_COVERAGE).
#define SAMPLE_COVERAGE
#include "blade_shading.glsl"
