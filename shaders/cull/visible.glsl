// Set 0: the cull's visible list (`Visible`, its texel view `visible_texels` under the lavapipe
// profile), allocated by `render::scene_gpu::SceneGpu`, written by the cull, read by the blade
// passes. Read with `visible_entry`.
#ifndef MEADOW_VISIBLE_GLSL
#define MEADOW_VISIBLE_GLSL
#include "common/frame.glsl"

// The cull's output (cull_emit.comp writes it): x the blade (`visible_blade` in cull.glsl), y
// its root height (a block field's) as a half float relative to the camera's height (low 16
// bits; a half float's step near the camera is under a millimetre, where a root 40 m up the
// ground would have been 3 cm off), fade and widening as unorm8 (`visible_scale`,
// `visible_unpack`).
// Fade in [0, 1] and widening in [1, lod.w] as unorm8, both exact at 1 (no LOD: the same blade).
uint visible_scale(float root_y, vec2 scale) {
    vec2 unit = vec2(scale.x, (scale.y - 1.0) / max(frame_values.lod.w - 1.0, 1e-6));
    uvec2 bytes = uvec2(round(clamp(unit, 0.0, 1.0) * 255.0));
    float above_eye = root_y - frame_values.camera_position.y;
    return (packHalf2x16(vec2(above_eye, 0.0)) & 0xffffu) | (bytes.x << 16) | (bytes.y << 24);
}

// (root height, fade, widening) of a visible entry's second word.
vec3 visible_unpack(uint word) {
    return vec3(unpackHalf2x16(word & 0xffffu).x + frame_values.camera_position.y, float((word >> 16) & 255u) / 255.0,
        1.0 + float(word >> 24) / 255.0 * (frame_values.lod.w - 1.0));
}

// A visible entry that draws nothing: the padding of a bucket's last instance (cull_scan.comp).
const uint VISIBLE_PADDING = 0xffffffffu;

#ifdef CULL_WRITER
layout(SCENE(Visible), std430) writeonly buffer Visible { uvec2 visible[]; };
#elif defined(TEXEL_TWINS)
// Its readers fetch it as RG32UI texels (`vk::buffer::TexelView`).
layout(SCENE(visible_texels)) uniform usamplerBuffer visible_texels;
uvec2 visible_entry(uint i) {
    return texelFetch(visible_texels, int(i)).xy;
}
#else
layout(SCENE(Visible), std430) readonly buffer Visible { uvec2 visible[]; };
uvec2 visible_entry(uint i) {
    return visible[i];
}
#endif

#endif
