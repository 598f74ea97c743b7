// Set 0: this frame's uniforms (`FrameUniforms`, common.glsl), owned by `render::layouts::SceneFrame`
// (one host-visible block per frame in flight, given as `Frame` and, for the lavapipe profile's
// cull, `FrameStorage`).
#ifndef MEADOW_FRAME_GLSL
#define MEADOW_FRAME_GLSL
#include "common/profile.glsl"

#if defined(FRAME_FROM_STORAGE) && defined(TEXEL_TWINS)
// The profile's rule (profile.glsl): the cull's passes read `frame`, whose values decide their
// branches, through a storage binding of the same block.
layout(SCENE(FrameStorage), std140) readonly buffer FrameStorage { FrameUniforms frame; };
layout(SCENE(Frame), std140) uniform Frame { FrameUniforms frame_values; };
#else
layout(SCENE(Frame), std140) uniform Frame { FrameUniforms frame; };
// One binding: `frame_values` is `frame`.
#define frame_values frame
#endif

// The far field's band at distance `d` from the band's eye (`render::far_rings::BandEye`): 0
// where the blades are whole, from `band_start` to a leash (`band_eye.w`) short of the blade
// range, 1 past it. The cull thins the blades by it, the far field fades in by it.
float far_band_ramp(float d, float band_start) {
    float end = frame_values.lod.x - frame_values.band_eye.w;
    return clamp((d - band_start) / max(end - band_start, 1e-3), 0.0, 1.0);
}

#endif
