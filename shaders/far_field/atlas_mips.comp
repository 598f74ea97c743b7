#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's atlas mips (`render::far_field::atlas`): level l + 1 as the mean of level l's
// 2 × 2 texels. The atlas is premultiplied (albedo and height times coverage, coverage), so the
// mean is the right filter for every channel and each level's mean coverage is level 0's.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba16f) uniform readonly image2D finer;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D coarser;

void main() {
    ivec2 at = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(at, imageSize(coarser)))) {
        return;
    }
    ivec2 from = 2 * at;
    vec4 sum = imageLoad(finer, from) + imageLoad(finer, from + ivec2(1, 0)) + imageLoad(finer, from + ivec2(0, 1))
        + imageLoad(finer, from + ivec2(1, 1));
    imageStore(coarser, at, 0.25 * sum);
}
