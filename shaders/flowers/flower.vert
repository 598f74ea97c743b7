#version 460
#extension GL_GOOGLE_include_directive : require
// The flowers' pass (`render::flowers`): each entry of the flowers' buckets of the cull's visible
// list is a head of petals on a stem. No vertex buffer: the pass's index list
// (`render::flowers::flower_indices`) names, per index, the flower k of its instance
// (BLADES_PER_INSTANCE entries) and a vertex code, k · FLOWER_STRIDE + code:
// - near bucket, codes 0.. : a stem of FLOWER_NEAR_STEM_SEGMENTS segments (2 vertices a level),
//   then a head of FLOWER_NEAR_PETALS petals (`head_vertex`: a centre and 2 vertices a petal);
// - far bucket, codes FLOWER_FAR_BASE.. : the head alone, a square of 4 vertices at the posed
//   stem's tip (the stem, 4 mm wide, is under a pixel wide there).
// The stem is the blade the flower took, posed as that blade: the response's pose records of its
// entry (the pose pass covers the flowers' buckets, `FLAG_POSE_CLASS`), or the neutral curve for a
// response with none (static blades). Its level points scale with the stem's own height. The head
// sits at the stem's tip, facing along the tip's tangent, so it nods as the stem bends.
#include "common/bindings.glsl"
#include "blades/blade_place.glsl"
#include "flowers/flowers.glsl"

const uint FLOWER_STRIDE = 32u; // render::flowers::STRIDE
const uint FLOWER_FAR_BASE = 23u; // render::flowers::FAR_BASE
const float FLOWER_FAR_SQUARE = 0.8; // render::flowers::FAR_SQUARE

layout(location = 0) out vec4 out_lit; // rgb: lit, fogged colour; a: fog transmittance

// Strip level `level` of a `segments`-segment stem `height` tall.
LevelPose stem_level(uint record, BladeInstance blade, float height, uint level, uint segments) {
    if ((RENDER_FLAGS & FLAG_EVAL_BLADE) != 0u) {
        return recorded_level(record, height, level, segments);
    }
    vec3 p[4];
    neutral_control_points(height, unpack_variation(blade.variation, 2), p);
    float t = float(level) / float(segments);
    LevelPose pose;
    pose.local = bezier_point(p[0], p[1], p[2], p[3], t);
    pose.tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
    pose.twist_cs = vec2(1.0, 0.0);
    pose.force = 0.0;
    return pose;
}

// A head's vertex, a star of `petals` petals around `tip` facing `axis`: vertex `v` of the head,
// 0 its centre, then around it 2 per petal, the notch before the petal and the petal's tip; with
// no petals (the far head) corner `v` of a square.
// Returns the world point; `color` the head's colour there (its centre darker and yellow).
vec3 head_vertex(vec3 tip, vec3 axis, FlowerLooks looks, uint v, uint petals, out vec3 color) {
    color = flower_head_color(looks.color);
    if (petals == 0u) {
        // The far head: a square's corners, as far out as the star's mean radius.
        vec3 ref = abs(axis.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 u = normalize(cross(axis, ref));
        float a = looks.turn + 0.5 * PI * float(v);
        return tip + (cos(a) * u + sin(a) * cross(axis, u)) * (FLOWER_FAR_SQUARE * looks.head_radius);
    }
    if (v == 0u) {
        color = vec3(0.85, 0.62, 0.06) * 0.6;
        return tip + axis * 0.004;
    }
    vec3 ref = abs(axis.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 u = normalize(cross(axis, ref));
    vec3 w = cross(axis, u);
    uint k = v - 1u;
    bool petal_tip = (k & 1u) != 0u;
    float a = looks.turn + 2.0 * PI * (float(k >> 1u) + (petal_tip ? 0.0 : -0.5)) / float(petals);
    // A star of rounded petals (notches at 0.55 of the radius) that cup upwards a little.
    float r = looks.head_radius * (petal_tip ? 1.0 : 0.55);
    float lift = looks.head_radius * (petal_tip ? 0.25 : 0.08);
    return tip + (cos(a) * u + sin(a) * w) * r + axis * lift;
}

void main() {
    uint index = uint(gl_VertexIndex);
    uint record = uint(gl_InstanceIndex) * BLADES_PER_INSTANCE + index / FLOWER_STRIDE;
    uint code = index % FLOWER_STRIDE;
    uvec2 entry = visible_entry(record);
    if (entry.x == VISIBLE_PADDING) {
        // The padding of the bucket's last instance: outside the clip volume.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        out_lit = vec4(0.0);
        return;
    }
    uint blade_index;
    BladeInstance blade = visible_instance(entry, blade_index);
    FlowerLooks looks = flower_looks(flower_id_hash(entry.x));
    // The density LOD's fade shrinks the head of a flower about to be dropped.
    looks.head_radius *= max(visible_unpack(entry.y).y, 0.15);
    bool far = code >= FLOWER_FAR_BASE;
    uint local = far ? code - FLOWER_FAR_BASE : code;
    uint segments = far ? 1u : FLOWER_NEAR_STEM_SEGMENTS;
    uint petals = far ? 0u : FLOWER_NEAR_PETALS;
    uint stem_vertices = far ? 0u : 2u * (segments + 1u);
    vec3 world;
    vec3 color;
    vec3 normal;
    float l;
    if (local < stem_vertices) {
        uint level = local >> 1u;
        float t = float(level) / float(segments);
        LevelPose pose = stem_level(record, blade, looks.stem_height, level, segments);
        PlacedLevel placed = place_level(blade, pose, vec2(1.0));
        world = placed.centre + placed.width_dir * ((float(local & 1u) - 0.5) * FLOWER_STEM_WIDTH);
        color = mix(vec3(0.03, 0.09, 0.02), vec3(0.10, 0.24, 0.05), t);
        normal = normalize(cross(placed.width_dir, placed.tangent));
        l = t;
    } else {
        LevelPose pose = stem_level(record, blade, looks.stem_height, segments, segments);
        PlacedLevel placed = place_level(blade, pose, vec2(1.0));
        vec3 axis = normalize(placed.tangent);
        world = head_vertex(placed.centre, axis, looks, local - stem_vertices, petals, color);
        normal = axis;
        l = 1.0;
    }
    // Two-sided, lit on the side facing the viewer (Belyaev §2.3's terms at height l, as a blade's).
    normal = dot(normal, frame_values.camera_position.xyz - world) < 0.0 ? -normal : normal;
    float l2 = l * l;
    vec3 lit = blade_radiance_l6(color, color, normal, frame_values.sun_direction.xyz, l, l2 * l2 * l2);
    float fog = fog_transmittance(world, frame_values.camera_position, frame_values.sky_color)
        * horizon_haze(length(world - frame_values.camera_position.xyz), uintBitsToFloat(frame_values.params.w));
    out_lit = vec4(lit * fog, fog);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
