#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's plants (`render::far_field::pass::FarPass`): the atlas's premultiplied albedo,
// coverage and mean height (`render::far_field::atlas`) at this point of the rectangle, lit with
// Belyaev's height terms (§2.3) at that height, fogged and encoded. A fragment is kept when a
// world-anchored hash lies under the coverage (per texel of the mip sampled, so every level keeps
// the mean coverage) and, per stretch of the rectangle a blade's place wide, another lies under
// the band's ramp and the view distance's end (a dither): no blending, no order.
//
// Its variant `blend` (`--fade blend`): no hashed test; the coverage times the fades is the
// alpha, the colour premultiplied by it, blended into the linear scene in the placement's order.
// Its variant `pressed` (where the blades read the pressed map, `render::animation::pressed`: it
// holds marks on frames with colliders or cuts and until they recover, `pressed_counts.y`): the
// plants are as tall as the map leaves the blades at the ground under each point, cut to their
// length and lowered by the press's lean, the atlas squeezed into that height.
// variant blend: FAR_BLEND
// variant pressed: FAR_PRESSED
// variant blend_pressed: FAR_BLEND FAR_PRESSED
#include "common/bindings.glsl"
#include "common/lighting.glsl"
#include "far_field/far_field.glsl"
#ifdef FAR_PRESSED
#define PRESSED_BINDING 5
#define PRESSED_ACCESS readonly
#include "animation/pressed.glsl"
#endif

// The atlas's two images (`render::far_field::atlas`): the premultiplied albedo and coverage, the
// premultiplied height along the blade and coverage.
layout(set = SET_PASS, binding = 3) uniform sampler2D far_atlas;
layout(set = SET_PASS, binding = 4) uniform sampler2D far_heights;

layout(location = 0) in vec2 in_along;
layout(location = 1) flat in uvec2 in_ids;
layout(location = 2) in vec3 in_sun;
layout(location = 3) in vec2 in_fresnel_fog;
layout(location = 4) in float in_distance;
layout(location = 5) in float in_force;
layout(location = 6) in float in_band;
layout(location = 7) in vec2 in_root;

layout(location = 0) out vec4 out_color;

void main() {
    uint rectangle = in_ids.y >> 2;
    // The footprint first: derivatives are defined only while every fragment of the quad runs.
    // The top of a tile is the plants' top.
    float tile = float(in_ids.y & 3u);
    // The plants' top over the ground here, a share of theirs (1: as grown, unpressed).
    float top = 1.0;
#ifdef FAR_PRESSED
    if (pressed_counts.y != 0u) {
        vec3 pressed = pressed_at(in_root);
        // press_points' lean: the chord turned by 2 asin(amount sin(lean / 2)).
        float lean = 2.0 * asin(min(length(pressed.xy), 1.0) * sin(0.5 * radians(PRESSED_LEAN_DEG)));
        top = max(pressed.z * cos(lean), 1e-3);
    }
#endif
    vec2 unwrapped = vec2((tile + in_along.x) / float(FAR_TILES), 1.0 - in_along.y);
    // A tile repeats across: a footprint wider than a tile averages the tile, so it is clamped to
    // one (a rectangle seen edge-on keeps its height profile instead of taking the coarsest level).
    // The footprint up the tile is the unpressed one squeezed by this point's top: `top` steps
    // from one pressed cell to the next, so its own derivative would spike at their edges.
    const float TILE = 1.0 / float(FAR_TILES);
    vec2 gx = dFdx(unwrapped) / vec2(1.0, top);
    vec2 gy = dFdy(unwrapped) / vec2(1.0, top);
    unwrapped.y = 1.0 - in_along.y / top;
    gx.x = clamp(gx.x, -TILE, TILE);
    gy.x = clamp(gy.x, -TILE, TILE);
    float fade = far_band(in_band) * far_end(in_distance);
    if (in_along.y > top) {
        discard;
    }
#ifndef FAR_BLEND
    float stretch = floor(in_along.x * FAR_TILE_WIDTH / FAR_STRETCH);
    if (far_unit(far_hash(ivec2(int(in_ids.x), int(stretch)), 16u + rectangle)) >= fade) {
        discard;
    }
#endif
    vec2 uv = vec2((tile + fract(in_along.x)) / float(FAR_TILES), unwrapped.y);
    // One level of detail for both images, from the clamped footprint (llvmpipe derives a level
    // per sample from gradients: twice the work, and the height only after the coverage test).
    const vec2 SIZE = vec2(float(FAR_TILES) * FAR_TILE_TEXELS.x, FAR_TILE_TEXELS.y);
    float level = max(0.0, 0.5 * log2(max(dot(gx * SIZE, gx * SIZE), dot(gy * SIZE, gy * SIZE))));
    vec4 color = textureLod(far_atlas, uv, level);
#ifdef FAR_BLEND
    float alpha = color.a * fade;
    if (alpha < 1.0 / 255.0) {
        discard;
    }
#else
    float lod = min(floor(0.5 + level), float(FAR_MIPS - 1u));
    ivec2 texel = ivec2(floor(uv * SIZE / exp2(lod)));
    uint h = far_hash(texel, in_ids.x ^ (rectangle * 0x68e31da4u) ^ (uint(lod) << 24));
    if (far_unit(h) >= color.a) {
        discard;
    }
#endif
    float mean_height = textureLod(far_heights, uv, level).r;
    float a = max(color.a, 1.0 / 255.0);
    vec3 albedo = color.rgb / a;
    if ((RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        // The blades' force view (blade_place.glsl): the wind's magnitude, green (none) to red.
        albedo = mix(vec3(0.05, 0.25, 0.03), vec3(0.8, 0.02, 0.01), clamp(in_force, 0.0, 1.0));
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_FAR) != 0u) {
        // The far field's plants (`--debug-view far`), lighter in the band.
        albedo = far_band(in_band) < 1.0 ? vec3(0.9, 0.35, 0.8) : vec3(0.6, 0.05, 0.5);
    }
    float l = clamp(mean_height / a, 0.0, 1.0);
    float l2 = l * l;
    float l6 = l2 * l2 * l2;
    vec3 lit = blade_radiance_terms(albedo, albedo, in_sun, l, l6);
    lit += FRESNEL_KS * l6 * in_fresnel_fog.x;
    vec3 fogged = mix(frame_values.sky_color.rgb, lit, in_fresnel_fog.y);
#ifdef FAR_BLEND
    // The scene is linear here (`render::settings::RenderSettings::linear_scene`): encode_output leaves it so.
    out_color = vec4(encode_output(fogged) * alpha, alpha);
#else
    out_color = vec4(encode_output(fogged), 1.0);
#endif
}
