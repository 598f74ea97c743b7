// Set 0: the blades (`BladeInstance`, common.glsl), owned by `render::scene_gpu::SceneGpu`
// (`Blades`, and its texel view `blade_texels` under the lavapipe profile). Read with `blade_record`.
#ifndef MEADOW_BLADE_RECORDS_GLSL
#define MEADOW_BLADE_RECORDS_GLSL
#include "common/profile.glsl"

#ifdef TEXEL_TWINS
// The blades (`BladeInstance`) as two RGBA32UI texels each: the scene's shaders read a blade with
// `blade_record`.
layout(SCENE(blade_texels)) uniform usamplerBuffer blade_texels;

BladeInstance blade_record(uint index) {
    uvec4 a = texelFetch(blade_texels, int(2u * index));
    uvec4 b = texelFetch(blade_texels, int(2u * index + 1u));
    BladeInstance blade;
    blade.position = uintBitsToFloat(a.xyz);
    blade.facing = uintBitsToFloat(a.w);
    blade.height = uintBitsToFloat(b.x);
    blade.width = uintBitsToFloat(b.y);
    blade.stiffness = uintBitsToFloat(b.z);
    blade.variation = b.w;
    return blade;
}
#else
layout(SCENE(Blades), std430) readonly buffer Blades { BladeInstance blades[]; };
BladeInstance blade_record(uint index) {
    return blades[index];
}
#endif

#endif
