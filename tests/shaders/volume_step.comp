#version 450
// A test pass's chain of four dependent dispatches over 3-D storage images (tests/graph_volume.rs),
// one file compiled once per step (`-DSTEP=n`, each variant declaring only its own bindings, so
// a step's pipeline uses only the images its step declares): step 0 writes the frame's source
// grid (rgba16f); step 1 gathers a 7-point stencil of the previous frame's grid (a storage read)
// and the source (sampled) into the scratch grid; step 2 relaxes the scratch into this frame's
// grid; step 3 samples this frame's grid into a buffer for the host. The values are small
// integers held exactly in float (sums below 2^24, `mod` by a power of two), so the CPU
// reference matches bit for bit.

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

const ivec3 DIMS = ivec3(8, 6, 4);

layout(push_constant) uniform Push {
    uint frame;
} push;

#if STEP == 0
layout(set = 0, binding = 0, rgba16f) uniform writeonly image3D Source;
#elif STEP == 1
layout(set = 0, binding = 1, r32f) uniform readonly image3D Previous;
layout(set = 0, binding = 2) uniform sampler3D SourceSampled;
layout(set = 0, binding = 3, r32f) uniform image3D Scratch;
#elif STEP == 2
layout(set = 0, binding = 3, r32f) uniform image3D Scratch;
layout(set = 0, binding = 4, r32f) uniform image3D Current;
#else
layout(set = 0, binding = 5) uniform sampler3D CurrentSampled;
layout(set = 0, binding = 6) writeonly buffer Readback { float values[]; };
#endif

#if STEP == 1
float at(ivec3 p) {
    return imageLoad(Previous, clamp(p, ivec3(0), DIMS - 1)).x;
}
#elif STEP == 2
float at(ivec3 p) {
    return imageLoad(Scratch, clamp(p, ivec3(0), DIMS - 1)).x;
}
#endif

#if STEP == 1 || STEP == 2
float neighbours(ivec3 p) {
    return at(p + ivec3(1, 0, 0)) + at(p - ivec3(1, 0, 0)) + at(p + ivec3(0, 1, 0)) + at(p - ivec3(0, 1, 0))
        + at(p + ivec3(0, 0, 1)) + at(p - ivec3(0, 0, 1));
}
#endif

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(p, DIMS))) {
        return;
    }
    int f = int(push.frame);
#if STEP == 0
    float a = float((p.x + 2 * p.y + 3 * p.z + f) % 8);
    float b = float((p.x * p.y + p.z + f) % 4);
    imageStore(Source, p, vec4(a, b, 0.0, 1.0));
#elif STEP == 1
    vec4 s = texelFetch(SourceSampled, p, 0);
    imageStore(Scratch, p, vec4(mod(neighbours(p) + 3.0 * at(p) + s.x + 2.0 * s.y, 4096.0)));
#elif STEP == 2
    imageStore(Current, p, vec4(mod(neighbours(p) + at(p), 4096.0)));
#else
    values[(p.z * DIMS.y + p.y) * DIMS.x + p.x] = texelFetch(CurrentSampled, p, 0).x;
#endif
}
