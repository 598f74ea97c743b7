#version 460
// The egui overlay's colour: the vertex colour times the texel, both gamma-space sRGB with
// premultiplied alpha, multiplied in gamma space as egui_glow does ("the only way to get text to
// look right"), blended `ONE, ONE_MINUS_SRC_ALPHA` by the pipeline. On a UNORM target (the
// viewer's swapchain, the offscreen targets) the values are written as they are, so the blend
// happens in gamma space, as egui_glow's on a non-sRGB framebuffer. On an *_SRGB target
// (`LINEAR_TARGET`) the format encodes what the shader writes: the colour is decoded first, as
// egui-wgpu's `fs_main_linear_framebuffer` does (the blend is then in linear space).

layout(constant_id = 0) const bool LINEAR_TARGET = false;

layout(set = 1, binding = 0) uniform sampler2D overlay_texture;

layout(location = 0) in vec4 v_color;
layout(location = 1) in vec2 v_uv;

layout(location = 0) out vec4 out_color;

vec3 linear_from_gamma(vec3 gamma) {
    bvec3 low = lessThan(gamma, vec3(0.04045));
    return mix(pow((gamma + 0.055) / 1.055, vec3(2.4)), gamma / 12.92, low);
}

void main() {
    vec4 color = v_color * texture(overlay_texture, v_uv);
    if (LINEAR_TARGET) {
        color.rgb = linear_from_gamma(color.rgb);
    }
    out_color = color;
}
