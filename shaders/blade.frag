#version 460
#extension GL_GOOGLE_include_directive : require
// Blade shading with the alpha test (or the outline as geometry): blade_shading.glsl.
#include "blade_shading.glsl"
