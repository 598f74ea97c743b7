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

// `scene::alpha` (half_width, the edge ramp) and SOLID_INSET of blade.vert.
float outline_half_width(float v) {
    return 0.5 * (1.0 - pow(v, 2.2)) * (0.8 + 0.2 * min(v / 0.08, 1.0));
}
const float SOLID_INSET = 0.35 * 0.22 - 0.06;

void main() {
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u) {
        // The outline is geometry (blade.vert narrows the quad to where the alpha reaches the
        // cutoff): no discard, so the depth test and write happen before shading and the
        // overdraw behind nearer blades is rejected early. The rim's darkening is the alpha of
        // `scene::alpha` at this point of the outline, computed instead of sampled.
        float half_width = outline_half_width(in_uv.y);
        float inside = half_width - abs(in_uv.x - 0.5) * 2.0 * max(half_width - SOLID_INSET, 0.0);
        float rim = clamp((inside + 0.06) / 0.22, 0.0, 1.0);
        vec3 solid = in_lit.rgb * mix(0.45, 1.0, rim) + frame.sky_color.rgb * (1.0 - in_lit.a);
        out_color = vec4(encode_output(solid), 1.0);
        return;
    }
    float alpha = texture(blade_alpha, in_uv).r;
    float coverage = 1.0;
    if ((RENDER_FLAGS & FLAG_ALPHA_TO_COVERAGE) != 0u) {
        // Alpha to coverage (`--msaa`): the cutoff's edge, sharpened to about one pixel wide
        // (alpha's screen-space rate, fwidth), covers the pixel's samples in proportion, so a
        // blade thinner than a pixel keeps a fraction of it instead of flickering in and out.
        coverage = clamp((alpha - ALPHA_CUTOFF) / max(fwidth(alpha), 1e-4) + 0.5, 0.0, 1.0);
    } else if (alpha < ALPHA_CUTOFF) {
        discard;
    }
    // Memberwise product with the alpha channel: the rim is darker (thesis 4.1).
    vec3 color = in_lit.rgb * mix(0.45, 1.0, alpha) + frame.sky_color.rgb * (1.0 - in_lit.a);
    out_color = vec4(encode_output(color), coverage);
}
