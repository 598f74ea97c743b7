#version 460
#extension GL_GOOGLE_include_directive : require
// Blade shading with the alpha test (or the outline as geometry): blade_shading.glsl. With
// `--msaa` and alpha to coverage, the variant `coverage` makes the outline's coverage per sample
// the fragment's sample mask (blade_shading.glsl, SAMPLE_COVERAGE).
// variant coverage: SAMPLE_COVERAGE
#include "blades/blade_shading.glsl"
