#version 460
#extension GL_GOOGLE_include_directive : require
// Blades by vertex pulling: no vertex buffer. Each instance draws BLADES_PER_INSTANCE blades as one
// triangle strip; gl_InstanceIndex and gl_VertexIndex select the blade and its strip vertex.
// Strip vertex 2k + side lies on Bézier spline `side` at t = k / segments (thesis 4.1). Blades in
// an instance are joined by repeating their first and last vertices (degenerate triangles), see
// `scene::bezier::Batching`.
//
// Texture mode (thesis 4.4.1): the blade's force is interpolated from its cluster's corners
// (eq. 3.6), expressed in the blade's frame, and selects a pose of the keyframe texture; the
// pose's displacement (eq. 3.4/3.9), scaled by the blade's height, is added to the neutral
// Bézier blade, and the width turns by the pose's twist.
#include "bindings.glsl"
#include "bezier.glsl"
#include "forces.glsl"
#include "keyframes.glsl"
#include "blade_select.glsl"
#include "lighting.glsl"
#include "field.glsl"
#include "terrain.glsl"
#include "rings.glsl"

// Lit per vertex (Gouraud): the blade's colour is affine along its length and its normal is the
// same across its width, so the fragment shader only adds the alpha-tested rim. Every varying
// costs llvmpipe setup and interpolation per triangle: four floats of light and fog replace the
// normal, world position and flat variation (ten components, 1.3-1.5x the floor's frame time).
// Per-cluster draws (`render::submission::ClusterPush`, Pelzer §7.4.2): the cluster's first
// blade; instance i of the draw is blade first_blade + i.
layout(push_constant) uniform ClusterPush {
    uint first_blade;
} cluster_push;

// Centroid: with --msaa, a pixel a thin blade covers only at some samples is shaded inside the
// blade, not at the pixel centre outside it (whose extrapolated u would read the outline's
// transparent edge and discard every covered sample). Without multisampling it changes nothing.
layout(location = 0) centroid out vec2 out_uv;         // u across, v root -> tip
// u at the pixel centre (not centroid): alpha to coverage's footprint across the blade.
layout(location = 2) out float out_u_center;
layout(location = 1) centroid out vec4 out_lit;        // rgb: lit, fogged blade colour before the rim; a: fog transmittance


// The animated blade at model level `m` (0..MODEL_SEGMENTS): local point, tangent, cos and sin
// of the twist, force magnitude.
struct LevelPose {
    vec3 local;
    vec3 tangent;
    vec2 twist_cs;
    float force;
};

LevelPose pose_records(uint record, float height, uint m) {
    // Evaluated once per blade and level by blade_pose.comp (thesis ch. 7 future work, with
    // compute): point, tangent and twist of this level in three words, no keyframe fetch.
    uint at = (record * (MODEL_SEGMENTS + 1u) + m) * POSE_WORDS;
    uint w1 = poses[at + 1u];
    vec4 tangent_force = unpackSnorm4x8(poses[at + 2u]);
    LevelPose pose;
    pose.local = vec3(unpackSnorm2x16(poses[at]), unpackSnorm2x16(w1 & 0xffffu).x) * (POSE_SCALE * height);
    pose.tangent = tangent_force.xyz;
    pose.twist_cs = unpackSnorm4x8(w1).zw;
    pose.force = tangent_force.w;
    return pose;
}

LevelPose pose_levels(vec3 p[4], KfSelection sel, float height, uint m) {
    vec4 here = deformed(p, sel, m, MODEL_SEGMENTS, height);
    vec4 below = m > 0u ? deformed(p, sel, m - 1u, MODEL_SEGMENTS, height) : here;
    vec4 above = m < MODEL_SEGMENTS ? deformed(p, sel, m + 1u, MODEL_SEGMENTS, height) : here;
    LevelPose pose;
    pose.local = here.xyz;
    pose.tangent = above.xyz - below.xyz;
    pose.twist_cs = vec2(cos(here.w), sin(here.w));
    return pose;
}

// A LOD bucket draws SEGMENTS <= MODEL_SEGMENTS segments: strip level `level` lies at model level
// level * MODEL_SEGMENTS / SEGMENTS, between two stored levels when SEGMENTS does not divide
// MODEL_SEGMENTS (a constant test: the interpolation compiles out otherwise). The fewer-segment
// blade samples the same curve.
const bool LEVELS_ALIGN = (MODEL_SEGMENTS % SEGMENTS) == 0u;

LevelPose animated(uint blade_index, uint record, BladeInstance blade, vec3 p[4], uint level, float t) {
    float at = float(level * MODEL_SEGMENTS) / float(SEGMENTS);
    uint m0 = LEVELS_ALIGN ? level * (MODEL_SEGMENTS / SEGMENTS) : uint(at);
    float frac = LEVELS_ALIGN ? 0.0 : at - float(m0);
    uint m1 = min(m0 + 1u, MODEL_SEGMENTS);
    if ((RENDER_FLAGS & FLAG_EVAL_BLADE) != 0u) {
        LevelPose pose = pose_records(record, blade.height, m0);
        if (!LEVELS_ALIGN && frac > 0.0) {
            LevelPose next = pose_records(record, blade.height, m1);
            pose.local = mix(pose.local, next.local, frac);
            pose.tangent = mix(pose.tangent, next.tangent, frac);
            pose.twist_cs = normalize(mix(pose.twist_cs, next.twist_cs, frac));
        }
        return pose;
    }
    float force;
    KfSelection sel = kf_select_blade(blade_index, blade, force);
    LevelPose pose;
    if (REPRESENTATION == REPRESENTATION_CURVE) {
        vec4 c1;
        vec4 c2;
        vec4 c3;
        curve_controls(sel, p, blade.height, c1, c2, c3);
        pose.local = bezier_point(p[0], c1.xyz, c2.xyz, c3.xyz, t);
        pose.tangent = bezier_tangent(p[0], c1.xyz, c2.xyz, c3.xyz, t);
        pose.twist_cs = vec2(cos(c1.w * t), sin(c1.w * t));
    } else {
        pose = pose_levels(p, sel, blade.height, m0);
        if (!LEVELS_ALIGN && frac > 0.0) {
            LevelPose next = pose_levels(p, sel, blade.height, m1);
            pose.local = mix(pose.local, next.local, frac);
            pose.tangent = mix(pose.tangent, next.tangent, frac);
            pose.twist_cs = normalize(mix(pose.twist_cs, next.twist_cs, frac));
        }
    }
    pose.force = force;
    return pose;
}

// `scene::alpha`: the outline's inset from its half width where alpha reaches the cutoff
// (cutoff * edge - 0.06).
const float SOLID_INSET = 0.35 * 0.22 - 0.06;

// Debug view `lod`: one colour per segment count.
vec3 lod_color(uint segments) {
    const vec3 colors[5] = vec3[5](vec3(0.9, 0.1, 0.1), vec3(0.95, 0.6, 0.05), vec3(0.9, 0.9, 0.1),
        vec3(0.1, 0.7, 0.2), vec3(0.1, 0.4, 0.9));
    return colors[min(findMSB(max(segments, 1u)), 4)];
}

void main() {
    const uint segments = SEGMENTS;
    uint blade_index = uint(gl_InstanceIndex) * BLADES_PER_INSTANCE + uint(gl_VertexIndex) / STRIP_STRIDE;
    // The cull's fade (the density LOD is about to drop the blade) and widening (its neighbours
    // were dropped): Belyaev §2.2 smooth transitions.
    vec2 lod_scale = vec2(1.0);
    // Where `--eval blade`'s pose record is: by blade, or with the cull by visible entry (the
    // blade-pose pass evaluates only the drawn blades).
    uint record = blade_index;
    uvec2 entry = uvec2(0u);
    bool tail = BLADES_PER_INSTANCE > 1u && blade_index >= frame.params.y;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        // Entry `blade_index` of the cull's list (instance * BLADES_PER_INSTANCE + k, the
        // bucket's first instance counting from its base); a bucket's last instance ends in
        // VISIBLE_PADDING.
        entry = visible[blade_index];
        tail = entry.x == VISIBLE_PADDING;
        blade_index = entry.x;
        lod_scale = visible_unpack(entry.y).yz;
    }
    if ((RENDER_FLAGS & FLAG_CLUSTER_PUSH) != 0u) {
        blade_index += cluster_push.first_blade;
    }
    if (tail) {
        // Tail of the last instance: a degenerate point outside the clip volume.
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        out_uv = vec2(0.0);
        out_u_center = 0.0;
        out_lit = vec4(0.0);
        return;
    }
    uint j = uint(gl_VertexIndex) % STRIP_STRIDE;
    uint strip = min(uint(max(int(j) - int(STRIP_LEAD), 0)), 2u * segments + 1u);
    BladeInstance blade;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        blade = visible_instance(entry, blade_index);
    } else {
        blade = blades[blade_index];
    }
    uint level = strip >> 1;
    float side = float(strip & 1u);
    float t = float(level) / float(segments);

    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));

    LevelPose pose;
    if (ANIMATION_MODE == MODE_STATIC) {
        pose.local = bezier_point(p[0], p[1], p[2], p[3], t);
        pose.tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
        pose.twist_cs = vec2(1.0, 0.0);
        pose.force = 0.0;
    } else {
        pose = animated(blade_index, record, blade, p, level, t);
    }
    vec3 local = pose.local * lod_scale.x;
    vec3 local_tangent = pose.tangent;
    vec2 twist_cs = pose.twist_cs;
    float force_magnitude = pose.force;
    float width = blade.width * lod_scale.x * lod_scale.y;
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u) {
        // The alpha-tested outline's width at this height (`scene::alpha`: half_width less the
        // cutoff's inset), as geometry: the far buckets draw it without a texture or discard.
        float half_width = 0.5 * (1.0 - pow(t, 2.2)) * (0.8 + 0.2 * min(t / 0.08, 1.0));
        width *= max(2.0 * (half_width - SOLID_INSET), 0.0);
    }

    // The width turns about +y by the twist: the blade faces the wind (Zhang Xia §3.2.5).
    vec3 width_dir = across * twist_cs.x - normal_dir * twist_cs.y;
    vec3 world = blade.position + across * local.x + vec3(0.0, local.y, 0.0) + normal_dir * local.z
        + width_dir * ((side - 0.5) * width);
    vec3 world_tangent = across * local_tangent.x + vec3(0.0, local_tangent.y, 0.0) + normal_dir * local_tangent.z;

    // Diffuse colour, darker at the root and brighter towards the tip (thesis 4.1).
    float hue = unpack_variation(blade.variation, 0);
    float brightness = 0.75 + 0.5 * unpack_variation(blade.variation, 1);
    vec3 root_color = mix(vec3(0.045, 0.12, 0.02), vec3(0.08, 0.13, 0.02), hue);
    vec3 tip_color = mix(vec3(0.22, 0.42, 0.06), vec3(0.42, 0.45, 0.10), hue);
    vec3 diffuse = mix(root_color, tip_color, t) * brightness;
    if ((RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        // Debug view: force magnitude from green (none) to red (the table's strongest pose).
        diffuse = mix(vec3(0.05, 0.25, 0.03), vec3(0.8, 0.02, 0.01), clamp(force_magnitude, 0.0, 1.0)) * mix(0.6, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_LOD) != 0u) {
        diffuse = lod_color(SEGMENTS) * mix(0.4, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_TILES) != 0u) {
        // A colour per tile of the cull (`scene::tiles`), from a hash of its cell.
        uvec2 cell = uvec2(max((blade.position.xz - vec2(frame.tile_grid.x)) / frame.tile_grid.y, vec2(0.0)));
        uint h = (cell.x * 73856093u) ^ (cell.y * 19349663u);
        h = (h ^ (h >> 13)) * 0x5bd1e995u;
        diffuse = (0.15 + 0.6 * vec3(h & 255u, (h >> 8) & 255u, (h >> 16) & 255u) / 255.0) * mix(0.5, 1.0, t);
    }
    // Two-sided: light the side facing the viewer, decided from the view vector so the strip's
    // triangle parity cannot flip it. Belyaev §2.3 is linear in the diffuse colour, and so is the
    // fog: colour = lit * rim + sky * (1 - fog) in blade.frag.
    vec3 n = normalize(cross(width_dir, world_tangent));
    n = dot(n, frame.camera_position.xyz - world) < 0.0 ? -n : n;
    float fog = fog_transmittance(world, frame.camera_position, frame.sky_color);
    vec3 lit = blade_radiance(diffuse, diffuse, n, frame.sun_direction.xyz, t);
    if ((RENDER_FLAGS & (FLAG_DEBUG_FORCE | FLAG_DEBUG_LOD | FLAG_DEBUG_TILES)) == 0u) {
        // Belyaev §2.3's Fresnel term on contour areas, over the terrain normal under the root.
        vec3 terrain_normal = (RENDER_FLAGS & FLAG_BLOCKS) != 0u
            ? relief_normal(blade.position.xz)
            : grid_terrain_normal(blade.position.xz, frame.terrain.x, frame.terrain.y, frame.params.z);
        vec3 fresnel = blade_fresnel(terrain_normal, normalize(frame.camera_position.xyz - world), t);
        lit = lit + fresnel;
        if ((RENDER_FLAGS & FLAG_DEBUG_FRESNEL) != 0u) {
            lit = fresnel; // the term alone, unfogged
            fog = 1.0;
        }
    }
    out_uv = vec2(side, t);
    out_u_center = side;
    out_lit = vec4(lit * fog, fog);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
