#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's atlas bake (atlas_bake.vert): the blade's outline alpha-tested as blade.frag
// tests it, and written unlit: its diffuse colour darkened at the rim as blade.frag darkens it
// (the albedo tiles), or its height along the blade (the height tiles), each with coverage 1 (the
// atlas is cleared to 0: premultiplied). A flower's stem (BAKE_STEM) is its stem's colour with no
// outline; its head (the variant `heads`) its head's colour at the top of the height.
// variant heads: BAKE_HEADS
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "common/field.glsl"
#include "common/ground.glsl"
#include "blades/blade_place.glsl"
#include "flowers/flowers.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 1) flat in uvec2 in_blade;

layout(location = 0) out vec4 out_color;

const float ALPHA_CUTOFF = 0.35; // scene::alpha::ALPHA_CUTOFF

const uint BAKE_STEM = 0x100u; // atlas_bake.vert's

void main() {
    uint output_code = in_blade.y & 0xffu;
#ifdef BAKE_HEADS
    out_color = output_code == 0u ? vec4(flower_head_color(in_blade.x), 1.0) : vec4(1.0, 0.0, 0.0, 1.0);
#else
    if ((in_blade.y & BAKE_STEM) != 0u) {
        // flower.vert's stem colour, root to tip.
        vec3 stem = mix(vec3(0.03, 0.09, 0.02), vec3(0.10, 0.24, 0.05), in_uv.y);
        out_color = output_code == 0u ? vec4(stem, 1.0) : vec4(in_uv.y, 0.0, 0.0, 1.0);
        return;
    }
    float alpha = texture(blade_alpha, in_uv).r;
    if (alpha < ALPHA_CUTOFF) {
        discard;
    }
    if (output_code == 0u) {
        vec3 albedo = blade_diffuse(in_blade.x, in_uv.y, 1.0) * mix(0.45, 1.0, alpha);
        out_color = vec4(albedo, 1.0);
    } else {
        out_color = vec4(in_uv.y, 0.0, 0.0, 1.0);
    }
#endif
}
