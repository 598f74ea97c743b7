#version 460
#extension GL_GOOGLE_include_directive : require
// Blade shading: alpha-tested outline, diffuse colour darkened at the rim by the alpha channel and
// brighter towards the tip (thesis 4.1), lit after Belyaev §2.3.
#include "bindings.glsl"
#include "bezier.glsl"
#include "lighting.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_world;
layout(location = 3) flat in uint in_variation;

layout(location = 0) out vec4 out_color;

const float ALPHA_CUTOFF = 0.35; // scene::alpha::ALPHA_CUTOFF

void main() {
    float alpha = texture(blade_alpha, in_uv).r;
    if (alpha < ALPHA_CUTOFF) {
        discard;
    }
    float hue = unpack_variation(in_variation, 0);
    float brightness = 0.75 + 0.5 * unpack_variation(in_variation, 1);
    vec3 root_color = mix(vec3(0.045, 0.12, 0.02), vec3(0.08, 0.13, 0.02), hue);
    vec3 tip_color = mix(vec3(0.22, 0.42, 0.06), vec3(0.42, 0.45, 0.10), hue);
    vec3 diffuse = mix(root_color, tip_color, in_uv.y) * brightness;
    // Memberwise product with the alpha channel: the rim is darker (thesis 4.1).
    diffuse *= mix(0.45, 1.0, alpha);
    if ((RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        float in_force = unpack_variation(in_variation, 3);
        // Debug view: force magnitude from green (none) to red (the table's strongest pose).
        diffuse = mix(vec3(0.05, 0.25, 0.03), vec3(0.8, 0.02, 0.01), clamp(in_force, 0.0, 1.0)) * mix(0.6, 1.0, in_uv.y);
    }

    // Two-sided: light the side facing the viewer. Decided from the view vector, not from
    // gl_FrontFacing, so the strip's triangle parity cannot flip it.
    vec3 n = normalize(in_normal);
    n = dot(n, frame.camera_position.xyz - in_world) < 0.0 ? -n : n;
    vec3 color = blade_radiance(diffuse, diffuse, n, frame.sun_direction.xyz, in_uv.y);
    color = apply_fog(color, in_world, frame.camera_position, frame.sky_color);
    out_color = vec4(encode_output(color, frame.params.w), 1.0);
}
