// Shared GPU data layout. The Rust mirrors are `render::frame::FrameUniforms` and
// `scene::blades::BladeInstance`; their sizes and offsets are asserted at compile time in Rust and
// read back through `blade_readback.comp` in the tests.
#ifndef MEADOW_COMMON_GLSL
#define MEADOW_COMMON_GLSL

// Per-frame constants (std140, 160 bytes).
struct FrameUniforms {
    mat4 view_proj;         // world -> clip (reversed infinite Z, Vulkan y down)
    vec4 camera_position;   // xyz eye, w simulation time (s)
    vec4 sun_direction;     // xyz unit vector towards the sun, w unused
    vec4 sky_color;         // rgb linear sky, w fog density (1/m)
    vec4 terrain;           // x grid origin (x = z), y cell size (m), zw unused
    uvec4 params;           // x segments, y blade count, z terrain cells per side, w 1 = encode sRGB
    uvec4 batching;         // x blades per instance, y vertices per blade, z leading repeats, w unused
};

// One blade (std430, 32 bytes).
struct BladeInstance {
    vec3 position;          // root, world space
    float facing;           // radians about +y; normal = (sin, 0, cos)
    float height;           // backbone length (m)
    float width;            // m
    float stiffness;        // relative joint stiffness
    uint variation;         // unorm8 x4: hue, brightness, lean, spare
};

#define BINDING_FRAME 0
#define BINDING_BLADES 1
#define BINDING_HEIGHTS 2
#define BINDING_BLADE_ALPHA 3

#endif
