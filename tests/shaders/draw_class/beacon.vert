#version 460
#extension GL_GOOGLE_include_directive : require
// tests/draw_class.rs: the beacons' pass draws its bucket of the cull's visible list, a blue
// upright square facing the camera at each beacon, found from its entry (`source_entry`: the ring
// slot and the beacon's rank, beacons.glsl; its height from the entry's second word).
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "beacons.glsl"

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
    uint rank;
    uint slot = source_entry(entry, rank);
    vec3 beacon = vec3(0.0, visible_unpack(entry.y).x, 0.0);
    beacon.xz = beacon_xz(slot, rank);
    uint corner = uint(gl_VertexIndex) % 4u;
    vec2 offset = vec2(float(corner & 1u), float(corner >> 1u)) - 0.5;
    vec3 to_eye = frame.camera_position.xyz - beacon;
    vec3 right = normalize(vec3(to_eye.z, 0.0, -to_eye.x));
    vec3 world = beacon + (right * offset.x + vec3(0.0, offset.y, 0.0)) * 0.3;
    out_color = vec3(0.0, 0.0, 1.0);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
