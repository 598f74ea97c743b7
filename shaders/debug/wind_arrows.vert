#version 460
#extension GL_GOOGLE_include_directive : require
// Debug view of the wind (`--debug-view wind`, `render::passes::wind_arrows`): the wind field the
// grass feels this frame, as an arrow at every `stride`-th cluster corner, on the slice `lift`
// above the ground (the height the fluid wind is sampled at, `render::wind::fluid::SAMPLE_HEIGHT`).
// Whatever the field (analytic, Perlin, fluid), it is the corners' velocity (m/s) the blades
// interpolate (`wind/wind_field.glsl`), with the point sources evaluated at the corner under
// delayed attenuation. Six vertices per arrow, a line list with no vertex buffer: the shaft from
// the corner along the wind (`metres_per_speed` m per m/s, at most 1.5 arrow spacings) and two
// strokes of its head. Coloured by speed: blue (calm) through cyan and yellow to red at
// KEYFRAME_WIND_SCALE (8 m/s, the strongest keyframed pose) and above. A stored field's corners
// are its one cluster grid; a block field's (FLAG_BLOCKS) the finest of its nested levels, around
// O's cell.
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "wind/wind_field.glsl"

layout(push_constant) uniform Arrows {
    float origin;           // a stored field: x = z of corner 0 (a block field's is the frame's)
    float spacing;          // m between two corners
    uint corners;           // corners per side
    uint stride;            // corners from one arrow to the next
    uint per_side;          // arrows per side
    float lift;             // m above the ground: the slice
    float metres_per_speed; // the shaft's length per m/s of wind
    float pad;
} arrows;

layout(location = 0) out vec3 out_color;

// Speed (m/s) as colour: blue, cyan, yellow, red at KEYFRAME_WIND_SCALE and above.
vec3 speed_color(float speed) {
    float t = clamp(speed / KEYFRAME_WIND_SCALE, 0.0, 1.0) * 3.0;
    vec3 blue = vec3(0.1, 0.25, 1.0), cyan = vec3(0.1, 0.9, 0.9);
    vec3 yellow = vec3(1.0, 0.9, 0.1), red = vec3(1.0, 0.1, 0.05);
    return t < 1.0 ? mix(blue, cyan, t) : t < 2.0 ? mix(cyan, yellow, t - 1.0) : mix(yellow, red, t - 2.0);
}

// `v` turned about the vertical by `angle` (radians).
vec3 turned(vec3 v, float angle) {
    float c = cos(angle), s = sin(angle);
    return vec3(c * v.x - s * v.z, v.y, s * v.x + c * v.z);
}

void main() {
    uint arrow = uint(gl_VertexIndex) / 6u;
    uint vertex = uint(gl_VertexIndex) % 6u;
    uvec2 corner = uvec2(arrow % arrows.per_side, arrow / arrows.per_side) * arrows.stride;
    bool blocks = (RENDER_FLAGS & FLAG_BLOCKS) != 0u;
    // A block field's finest level: WIND_LEVEL_CLUSTERS clusters about O's cell (`level_cluster`).
    float spacing = blocks ? frame.terrain.y : arrows.spacing;
    float origin = blocks ? 0.5 * frame.field.x - 0.5 * float(WIND_LEVEL_CLUSTERS) * spacing : arrows.origin;
    vec2 p = vec2(origin) + vec2(corner) * spacing;
    float ground = ground_height(p);
    vec3 base = vec3(p.x, ground + arrows.lift, p.y);
    vec3 wind = with_point_sources(wind_corner(corner.y * arrows.corners + corner.x), p).xyz;
    vec3 shaft = wind * arrows.metres_per_speed;
    float longest = 1.5 * spacing * float(arrows.stride);
    shaft *= min(1.0, longest / max(length(shaft), 1e-6));
    vec3 tip = base + shaft;
    vec3 back = -0.3 * shaft;
    vec3 world = vertex == 0u ? base
        : vertex == 3u ? tip + turned(back, 0.45)
        : vertex == 5u ? tip + turned(back, -0.45)
        : tip;
    out_color = speed_color(length(wind));
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
