// Shared GPU data layout. The Rust mirrors are `render::frame::FrameUniforms` and
// `scene::blades::BladeInstance`; their sizes and offsets are asserted at compile time in Rust and
// read back through `blade_readback.comp` in the tests.
#ifndef MEADOW_COMMON_GLSL
#define MEADOW_COMMON_GLSL

// Per-frame constants (std140, 176 bytes).
struct FrameUniforms {
    mat4 view_proj;         // world -> clip (reversed infinite Z, Vulkan y down)
    vec4 camera_position;   // xyz eye, w simulation time (s)
    vec4 sun_direction;     // xyz unit vector towards the sun, w unused
    vec4 sky_color;         // rgb linear sky, w fog density (1/m)
    vec4 terrain;           // x grid origin (x = z), y cell size (m), zw unused
    uvec4 params;           // x segments, y blade count, z terrain cells per side, w unused
    uvec4 keyframes;        // x magnitudes, y angles, z point sources, w cluster corners per side
    uvec4 keyframe_shape;   // x records per pose, y colliders (emitters after the sources), zw unused
};

// How the blades are animated is fixed per pipeline by specialization constants, not read from
// uniforms: llvmpipe (and most GPUs) compile a uniform branch into masked code that pays for every
// path, so each configuration gets its own pipeline with the other paths compiled out.
// `render::specialization::Specialization` fills them, in this order.
layout(constant_id = 1) const uint ANIMATION_MODE = 0u;     // 0 static, 1 texture, 2 uniform
layout(constant_id = 2) const uint SMOOTHING = 0u;          // 0 nearest, 1 linear (eq. 3.13), 2 slerp (eq. 3.14)
layout(constant_id = 3) const uint KEYFRAME_ENCODING = 1u;  // 0 rgba8x2, 1 unorm16, 2 float32; 3 thesis-merged,
                                                            // 4 snorm16x2 uniform words
layout(constant_id = 4) const uint ATTENUATION = 0u;        // 0 cluster, 1 blade (thesis 4.5)
layout(constant_id = 5) const uint REPRESENTATION = 0u;     // 0 vertex levels, 1 Bézier curve
layout(constant_id = 6) const uint RENDER_FLAGS = 0u;       // FLAG_DEBUG_FORCE | FLAG_EVAL_BLADE | FLAG_CLUSTER_PUSH
// Blade geometry (`scene::bezier::Batching`): with constants, the vertex shader's divisions by
// the strip length become multiplications, and one blade per instance needs none at all.
layout(constant_id = 7) const uint SEGMENTS = 4u;
layout(constant_id = 8) const uint BLADES_PER_INSTANCE = 1u;
// 1: the shaders encode sRGB (UNORM targets); 0: the target's *_SRGB format does.
layout(constant_id = 9) const uint ENCODE_SRGB = 1u;
const uint STRIP_LEAD = BLADES_PER_INSTANCE > 1u ? 1u : 0u;     // repeats of a strip's first vertex
const uint STRIP_STRIDE = 2u * (SEGMENTS + 1u) + 2u * STRIP_LEAD; // vertices per blade

// Per-blade cluster record (std430, 8 bytes): eq. 3.7 weights precomputed.
struct BladeCluster {
    uint corner;            // corner of the cluster with the smallest x and z
    uint weights;           // unorm8 x4: (x0,z0) (x1,z0) (x0,z1) (x1,z1)
};

// One blade (std430, 32 bytes).
struct BladeInstance {
    vec3 position;          // root, world space
    float facing;           // radians about +y; normal = (sin, 0, cos)
    float height;           // backbone length (m)
    float width;            // m
    float stiffness;        // relative joint stiffness
    uint variation;         // unorm8 x4: hue, brightness, lean, spare (the debug view's force in blade.frag)
};

#define BINDING_FRAME 0
#define BINDING_BLADES 1
#define BINDING_HEIGHTS 2
#define BINDING_BLADE_ALPHA 3
#define BINDING_CLUSTERS 4
#define BINDING_CORNERS 5
#define BINDING_EMITTERS 6
#define BINDING_KEYFRAMES 7
#define BINDING_KEYFRAME_WORDS 8
#define BINDING_POSES 9

#define FLAG_DEBUG_FORCE 1u  // colour blades by force magnitude (thesis fig. 4.5 / 6.1c)
#define FLAG_EVAL_BLADE 2u   // poses selected once per blade by blade_pose.comp
#define FLAG_CLUSTER_PUSH 4u // per-cluster draws: the first blade is a push constant (`meadow overhead`)

const float PI = 3.14159265;

#define MODE_STATIC 0u
#define MODE_TEXTURE 1u
#define MODE_UNIFORM 2u

#endif
