// Blade shading (blade.frag, and its variant `coverage` with SAMPLE_COVERAGE): alpha-tested
// outline, the colour lit per vertex (blade.vert, Belyaev §2.3) darkened at the rim by the alpha
// channel (thesis 4.1), then the fog's sky part added.
#ifndef MEADOW_BLADE_SHADING_GLSL
#define MEADOW_BLADE_SHADING_GLSL
#include "common/bindings.glsl"
#include "common/lighting.glsl"
#include "blades/outline.glsl"

layout(location = 0) centroid in vec2 in_uv; // centroid: see blade.vert
layout(location = 1) centroid in vec4 in_lit;
layout(location = 2) in float in_u_center; // u at the pixel centre, for alpha to coverage

layout(location = 0) out vec4 out_color;

const float ALPHA_CUTOFF = 0.35; // scene::alpha::ALPHA_CUTOFF

#ifdef SAMPLE_COVERAGE
// Alpha to coverage, per sample (`--msaa`, blade.frag's variant `coverage`): which of the pixel's samples lie
// inside the alpha-tested outline (`scene::alpha`: |u - 0.5| <= half_width - SOLID_INSET at
// height v), from u at the pixel centre and its screen-space rate; the result is the fragment's
// sample mask. A blade thinner than a pixel covers the samples its outline covers, instead of all
// the samples of its quad when the centroid passes (the alpha test) or none when it does not.
// The hardware's own alpha to coverage maps one alpha per pixel to a mask by an
// implementation-defined rule (llvmpipe: sample s when alpha > s / N, a fixed pattern that
// correlates with the geometric coverage and thins far blades: measured); this is the outline's
// exact coverage at the samples' standard locations (`standardSampleLocations`, checked).
const vec2 STANDARD_LOCATIONS_2[2] = vec2[2](vec2(0.75, 0.75), vec2(0.25, 0.25));
const vec2 STANDARD_LOCATIONS_4[4] =
    vec2[4](vec2(0.375, 0.125), vec2(0.875, 0.375), vec2(0.125, 0.625), vec2(0.625, 0.875));
const vec2 STANDARD_LOCATIONS_8[8] = vec2[8](vec2(0.5625, 0.3125), vec2(0.4375, 0.6875), vec2(0.8125, 0.5625),
    vec2(0.3125, 0.1875), vec2(0.1875, 0.8125), vec2(0.0625, 0.4375), vec2(0.6875, 0.9375), vec2(0.9375, 0.0625));
const vec2 STANDARD_LOCATIONS_16[16] = vec2[16](vec2(0.5625, 0.5625), vec2(0.4375, 0.3125), vec2(0.3125, 0.625),
    vec2(0.75, 0.4375), vec2(0.1875, 0.375), vec2(0.625, 0.8125), vec2(0.8125, 0.6875), vec2(0.6875, 0.1875),
    vec2(0.375, 0.875), vec2(0.5, 0.0625), vec2(0.25, 0.125), vec2(0.125, 0.75), vec2(0.0, 0.5), vec2(0.9375, 0.25),
    vec2(0.875, 0.9375), vec2(0.0625, 0.0));

vec2 sample_location(uint s) {
    if (MSAA_SAMPLES == 2u) {
        return STANDARD_LOCATIONS_2[s];
    } else if (MSAA_SAMPLES == 8u) {
        return STANDARD_LOCATIONS_8[s];
    } else if (MSAA_SAMPLES == 16u) {
        return STANDARD_LOCATIONS_16[s];
    }
    return STANDARD_LOCATIONS_4[s];
}

int outline_sample_mask(float u, float v) {
    float edge = max(outline_half_width(v) - SOLID_INSET, 0.0);
    vec2 rate = vec2(dFdx(u), dFdy(u));
    int mask = 0;
    for (uint s = 0u; s < MSAA_SAMPLES; s++) {
        if (abs(u + dot(rate, sample_location(s) - 0.5) - 0.5) <= edge) {
            mask |= 1 << s;
        }
    }
    return mask;
}
#endif

void main() {
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u && SEGMENTS == 1u) {
        // The one-segment bucket: blade.vert lit the blade with the rim's fit over its triangle
        // (`scene::alpha::ONE_SEGMENT_SHADE_ROOT`); no (u, v) to interpolate, no rim to compute.
        out_color = vec4(encode_output(in_lit.rgb + frame.sky_color.rgb * (1.0 - in_lit.a)), 1.0);
        return;
    }
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
#ifdef SAMPLE_COVERAGE
    int mask = outline_sample_mask(in_u_center, in_uv.y);
    if (mask == 0) {
        discard;
    }
    gl_SampleMask[0] = mask;
#else
    if (alpha < ALPHA_CUTOFF) {
        discard;
    }
#endif
    // Memberwise product with the alpha channel: the rim is darker (thesis 4.1). The rim's
    // darkest is the cutoff's, as with the alpha test: a fragment kept per sample whose centroid
    // lies past the cutoff only covers less of the pixel.
    vec3 color = in_lit.rgb * mix(0.45, 1.0, max(alpha, ALPHA_CUTOFF)) + frame.sky_color.rgb * (1.0 - in_lit.a);
    out_color = vec4(encode_output(color), 1.0);
}

#endif
