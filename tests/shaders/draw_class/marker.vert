#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the markers' pass draws its bucket of the cull's visible list, an upright
// square facing the camera half-way up each claimed blade; an instance is BLADES_PER_INSTANCE
// entries of four vertices (the class's index list, `render::draw_class::DrawClass::bucket_draw`).
#include "common/bindings.glsl"
#include "common/field.glsl"

layout(location = 0) out vec3 out_color;

void main() {
    uint entry_index = uint(gl_InstanceIndex) * BLADES_PER_INSTANCE + uint(gl_VertexIndex) / 4u;
    uvec2 entry = visible_entry(entry_index);
    if (entry.x == VISIBLE_PADDING) {
        // Outside the clip volume: the padding of the bucket's last instance draws nothing.
        gl_Position = vec4(2.0, 2.0, 0.5, 1.0);
        out_color = vec3(0.0);
        return;
    }
    uint blade_index;
    BladeInstance blade = visible_instance(entry, blade_index);
    uint corner = uint(gl_VertexIndex) % 4u;
    vec2 offset = vec2(float(corner & 1u), float(corner >> 1u)) - 0.5;
    vec3 to_eye = frame.camera_position.xyz - blade.position;
    vec3 right = normalize(vec3(to_eye.z, 0.0, -to_eye.x));
    vec3 world = blade.position + vec3(0.0, 0.5 * blade.height, 0.0) + (right * offset.x + vec3(0.0, offset.y, 0.0)) * 0.08;
    out_color = vec3(1.0, 0.0, 0.0);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
