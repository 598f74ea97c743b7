#version 460
#extension GL_GOOGLE_include_directive : require
// Blade shading: alpha-tested outline, the colour lit per vertex (blade.vert, Belyaev §2.3)
// darkened at the rim by the alpha channel (thesis 4.1), then the fog's sky part added.
#include "bindings.glsl"
#include "lighting.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 1) in vec4 in_lit;

layout(location = 0) out vec4 out_color;

const float ALPHA_CUTOFF = 0.35; // scene::alpha::ALPHA_CUTOFF

// Far LOD buckets (FLAG_SOLID_OUTLINE): the mean of the rim's darkening across a blade, for
// blades a few pixels wide whose outline is geometry.
const float SOLID_RIM = 0.8;

void main() {
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u) {
        // No discard: the depth test and write happen before shading, so the far field's overdraw
        // behind nearer blades is rejected early.
        out_color = vec4(encode_output(in_lit.rgb * SOLID_RIM + frame.sky_color.rgb * (1.0 - in_lit.a)), 1.0);
        return;
    }
    float alpha = texture(blade_alpha, in_uv).r;
    if (alpha < ALPHA_CUTOFF) {
        discard;
    }
    // Memberwise product with the alpha channel: the rim is darker (thesis 4.1).
    vec3 color = in_lit.rgb * mix(0.45, 1.0, alpha) + frame.sky_color.rgb * (1.0 - in_lit.a);
    out_color = vec4(encode_output(color), 1.0);
}
