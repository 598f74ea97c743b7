#version 460
#extension GL_GOOGLE_include_directive : require
// tests/new_model.rs: a wind field defined outside the library, a uniform 3-D wind. Each step it
// writes every cluster corner of the frame (`Corners`, the one quantity every blade response
// samples through wind/wind_field.glsl): the velocity in m/s and full exposure. Its only set is
// its own (set 0, numbered here); the velocity and the corner count are push constants.

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) writeonly buffer Corners { vec4 corners[]; };

layout(push_constant) uniform UniformWind {
    vec4 velocity; // xyz m/s, w unused
    uint count;    // corners over every level
} wind;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < wind.count) {
        corners[i] = vec4(wind.velocity.xyz, 1.0);
    }
}
