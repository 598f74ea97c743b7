#version 460
#extension GL_GOOGLE_include_directive : require
// Ground under the grass: earthy green, Lambert plus sky ambient, fogged like the blades.
#include "bindings.glsl"
#include "lighting.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_world;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(in_normal);
    vec3 albedo = vec3(0.07, 0.085, 0.03);
    float lambert = max(dot(n, frame.sun_direction.xyz), 0.0);
    vec3 color = albedo * (vec3(0.35, 0.38, 0.45) + vec3(1.2, 1.1, 0.95) * lambert);
    color = apply_fog(color, in_world, frame.camera_position, frame.sky_color);
    out_color = vec4(encode_output(color), 1.0);
}
