#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's atlas bake (atlas_bake.vert): the blade's outline alpha-tested as blade.frag
// tests it, and written unlit: its diffuse colour darkened at the rim as blade.frag darkens it
// (the albedo tiles), or its height along the blade (the height tiles), each with coverage 1 (the
// atlas is cleared to 0: premultiplied).
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "blades/blade_place.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 1) flat in uvec2 in_blade;

layout(location = 0) out vec4 out_color;

const float ALPHA_CUTOFF = 0.35; // scene::alpha::ALPHA_CUTOFF

void main() {
    float alpha = texture(blade_alpha, in_uv).r;
    if (alpha < ALPHA_CUTOFF) {
        discard;
    }
    if (in_blade.y == 0u) {
        vec3 albedo = blade_diffuse(in_blade.x, in_uv.y, 1.0) * mix(0.45, 1.0, alpha);
        out_color = vec4(albedo, 1.0);
    } else {
        out_color = vec4(in_uv.y, 0.0, 0.0, 1.0);
    }
}
