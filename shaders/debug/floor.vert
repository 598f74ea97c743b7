#version 460
#extension GL_GOOGLE_include_directive : require
// Floor reference (`--mode floor`): the blades' triangles pre-expanded on the CPU into a vertex
// buffer, only transformed here: the least a driver needs for this geometry.
#include "common/bindings.glsl"

layout(location = 0) in vec3 position;

void main() {
    gl_Position = frame.view_proj * vec4(position, 1.0);
}
