#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's plants (`render::far_field::pass::FarPass`): instance i is placed plant i
// (far_place.comp), vertex 4 k + c corner c of its rectangle k. Billboards (Zhang Xia §4.1): six
// half-planes from the plant's axis, 60° apart; stars (Pelzer §7.3): three quads crossing at it.
// Each rectangle stands on the ground at both its bottom corners, a plant's height tall; its top
// corners lean by the blade response's tip offset for the wind the field gives there (Zhang Xia
// §4.2: the segment points of the bottom and top of the plants), so the far field sways with the
// blades in the same wind. Lit per vertex with the rectangle's normal (Belyaev §2.3, its Fresnel
// term over the ground's normal): the direction terms here, the height terms per fragment from
// the atlas's mean height (far.frag).
//
// Its variant `blend` (`--fade blend`, Zhang Xia §5.4): a plant's pieces far to near. Either mesh
// is drawn as six half-planes from the axis (a star's three quads as their halves: the same
// surface), the one turned most away from the eye first, then its neighbours by turns, the one
// facing the eye last: half-planes on one side of the axis cover those behind them on that side
// and never those on the other.
// variant blend: FAR_BLEND
#include "common/bindings.glsl"
#include "common/ground.glsl"
#include "common/lighting.glsl"
#include "wind/wind_field.glsl"
#include "animation/forces.glsl"
#include "far_field/far_field.glsl"

layout(set = SET_PASS, binding = 1, std430) readonly buffer FarPlants { FarPlant plants[]; };

layout(location = 0) out vec2 out_along;   // x from the axis in atlas tiles (unwrapped), y 0 bottom to 1 top
layout(location = 1) flat out uvec2 out_ids; // x the plant's hash, y tile (low 2 bits) | rectangle << 2
layout(location = 2) out vec3 out_sun;     // the direction terms: max(N·L, 0) + C max(-N·L, 0)
layout(location = 3) out vec2 out_fresnel_fog; // x (1 - N_L·V)^10, y the fog's transmittance
layout(location = 4) out float out_distance; // from the camera (m)
layout(location = 5) out float out_force;    // `--debug-view force`: the wind's speed in the keyframes' force units
layout(location = 6) out float out_band;     // from the band's eye (m, `render::far_rings::BandEye`)
layout(location = 7) out vec2 out_root;      // the ground under the point (x, z relative to O): the pressed map's place

// The colliders' push on a plant's upright of `height` m rooted at `root` (relative to O), as the
// wind that would push as hard (m/s): each collider's reach-weighted force (animation/forces.glsl's
// `collider_force`, eq. C.1–C.3, in the keyframes' units) joins the wind its tip leans by, as it
// joins a blade's force, so a far plant leans away from a collider as a near blade at the same
// place does. Only the colliders whose ground ellipse may hold the root (collider_bins.glsl).
vec2 collider_wind(vec3 root, float height) {
    return add_collider_push_at(vec2(0.0), root, height) * KEYFRAME_WIND_SCALE;
}

// The tip's move per metre of height under wind `w` (m/s, xz), from the response's table.
vec3 tip_lean(vec2 w) {
    float speed = length(w);
    float at = clamp(speed / FAR_TIP_MAX, 0.0, 1.0) * float(FAR_TIP_TABLE - 1u);
    uint i = min(uint(at), FAR_TIP_TABLE - 2u);
    vec2 entry = mix(far.tips[i].xy, far.tips[i + 1u].xy, at - float(i));
    vec2 along = speed > 1e-4 ? w / speed : vec2(0.0);
    return vec3(along.x * entry.x, entry.y, along.y * entry.x);
}

void main() {
    FarPlant plant = plants[gl_InstanceIndex];
    uint piece = uint(gl_VertexIndex) >> 2;
    uint corner = uint(gl_VertexIndex) & 3u;
    float width = plant.centre_width.w;
    float turn = uintBitsToFloat(plant.hash_turn_ring.y);
    bool outer = (corner & 1u) != 0u;
    bool top = corner >= 2u;
    bool star = far.counts.y == FAR_MESH_STARS;
    vec2 eye = frame_values.camera_position.xz;
#ifdef FAR_BLEND
    // The half-plane nearest the direction away from the eye, then the others alternately.
    const int AWAY_FIRST[6] = int[6](0, 1, -1, 2, -2, 3);
    vec2 away = plant.centre_width.xz - eye;
    int farthest = int(round((atan(away.y, away.x) - turn) / (PI / 3.0)));
    // farthest lies in [-9, 3] (atan's range less the turn's), the sum in [-11, 6]: made positive
    // before the modulo.
    uint half_plane = uint(farthest + AWAY_FIRST[piece] + 18) % 6u;
    // A star's quad, and the side of its axis the half is.
    uint rectangle = star ? half_plane % 3u : half_plane;
    float side = half_plane >= 3u && star ? -1.0 : 1.0;
    // Its ends' signed distances from the axis (m) along the rectangle.
    vec2 ends = vec2(0.0, 0.5 * side * width);
#else
    uint rectangle = piece;
    // A half-plane from the axis, a quad across it.
    vec2 ends = vec2(star ? -0.5 * width : 0.0, 0.5 * width);
#endif
    turn += float(rectangle) * (PI / 3.0);
    vec2 dir = vec2(cos(turn), sin(turn));
    // The corner's signed distance from the axis (m).
    float from_axis = outer ? ends.y : ends.x;
    vec2 root = plant.centre_width.xz + dir * from_axis;
    // A rectangle wholly nearer than the band's start would be wholly discarded by the fade
    // (far.frag, by the distance in 3-D from the band's eye): not rasterized at all. Its ends'
    // distance across the ground, and the band's eye's height over its top at most.
    vec3 band = frame_values.band_eye.xyz;
    float across = max(length(plant.centre_width.xz + dir * ends.x - band.xz), length(plant.centre_width.xz + dir * ends.y - band.xz));
    float up = abs(band.y - plant.centre_width.y) + far.reach.y;
    float farther_end = sqrt(across * across + up * up);
    // A rectangle seen nearly edge-on covers a sliver of pixels at the cost of whole quads: the
    // plant's other rectangles, 60° away, cover for it.
    vec2 to_eye = normalize(eye - plant.centre_width.xz);
    bool edge_on = abs(dot(vec2(-dir.y, dir.x), to_eye)) < FAR_EDGE_ON;
    if (farther_end < far.rings.z || edge_on) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    vec3 world = vec3(root.x, ground_height(root), root.y);
    float height = far.reach.y;
    out_force = 0.0;
    if (top || (RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        vec4 wind = with_point_sources(levels_wind(root), root);
        wind.xz += collider_wind(world, height);
        out_force = length(wind.xz) / KEYFRAME_WIND_SCALE;
        if (top) {
            world += (vec3(0.0, 1.0, 0.0) + tip_lean(wind.xz)) * height;
        }
    }
    uint tile = (plant.hash_turn_ring.x >> (2u * rectangle)) & 3u;
    if (FLOWER_SHARE != 0u) {
        // With flowers, tiles 0 and 1 are grass alone and tiles 2 and 3 flowers at the share
        // far.rings.w (`render::far_field::atlas`): this rectangle takes them with the chance that
        // gives the share of the flowers here, flowers.glsl's `flower_claimed` (FLOWER_SHARE times
        // the green over the red of the cover), so the far flowers follow the covering map.
        vec2 covers = ground_covers(plant.centre_width.xz);
        float here = min(uintBitsToFloat(FLOWER_SHARE) * covers.y / max(covers.x, 1.0 / 255.0), 1.0);
        float chance = far.rings.w > 0.0 ? here / far.rings.w : 0.0;
        bool flowers = far_unit(far_hash(ivec2(int(plant.hash_turn_ring.x), int(rectangle)), 5u)) < chance;
        tile = (tile & 1u) + (flowers ? 2u : 0u);
    }
    // Metres from the axis: a point of the rectangle keeps its texel and its fade stretch as the
    // width grows with the distance (world-anchored, like the plant).
    out_along = vec2(from_axis / FAR_TILE_WIDTH, top ? 1.0 : 0.0);
    out_ids = uvec2(plant.hash_turn_ring.x, tile | (rectangle << 2));
    vec3 to_camera = frame_values.camera_position.xyz - world;
    vec3 n = vec3(-dir.y, 0.0, dir.x);
    n = dot(n, to_camera) < 0.0 ? -n : n;
    out_sun = blade_sun_terms(n, frame_values.sun_direction.xyz);
    float c = 1.0 - clamp(dot(ground_normal(root), normalize(to_camera)), 0.0, 1.0);
    float c2 = c * c;
    out_distance = length(to_camera);
    out_band = length(world - band);
    out_root = root;
    float fog = fog_transmittance(world, frame_values.camera_position, frame_values.sky_color);
    out_fresnel_fog = vec2(c2 * c2 * c2 * c2 * c2, fog * horizon_haze(out_distance, far.reach.x));
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
