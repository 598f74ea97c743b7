// A posed blade level placed in the world and lit: blade.vert does it at every strip vertex, and
// with the cull and pose records blade_levels.comp does it once per level of each drawn blade
// (its vertex shader then only widens and projects). One definition, so both light alike.
#ifndef MEADOW_BLADE_PLACE_GLSL
#define MEADOW_BLADE_PLACE_GLSL
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "common/lighting.glsl"
#include "common/field.glsl"
#include "common/ground.glsl"
#include "blades/outline.glsl"

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

// Strip level `level` of a `segments`-segment blade from its pose records: it lies at model level
// level * MODEL_SEGMENTS / segments, between two stored levels when `segments` does not divide
// MODEL_SEGMENTS (a constant test where `segments` is the constant SEGMENTS). The fewer-segment
// blade samples the same curve (`model_level`, common.glsl, finds the two).
LevelPose recorded_level(uint record, float height, uint level, uint segments) {
    float frac;
    uint m0 = model_level(level, segments, frac);
    LevelPose pose = pose_records(record, height, m0);
    if (frac > 0.0) {
        LevelPose next = pose_records(record, height, min(m0 + 1u, MODEL_SEGMENTS));
        pose.local = mix(pose.local, next.local, frac);
        pose.tangent = mix(pose.tangent, next.tangent, frac);
        pose.twist_cs = normalize(mix(pose.twist_cs, next.twist_cs, frac));
    }
    return pose;
}

// A level placed in the world: its centre-line point, the unit vector across it (turned by the
// twist), its full width (the cull's fade and widening applied; the outline's taper is the vertex
// shader's) and its tangent. The fade narrows a blade the density LOD is about to drop and leaves
// its height: shrinking both made the thinned field's mid and far distance less like brute
// force's (1M blades, default camera: 8x8 mean difference 0.455 % shrinking both, 0.415 % the
// width alone).
struct PlacedLevel {
    vec3 centre;
    vec3 width_dir;
    float width;
    vec3 tangent;
};

PlacedLevel place_level(BladeInstance blade, LevelPose pose, vec2 lod_scale) {
    vec3 across = vec3(cos(blade.facing), 0.0, -sin(blade.facing));
    vec3 normal_dir = vec3(sin(blade.facing), 0.0, cos(blade.facing));
    vec3 local = pose.local;
    PlacedLevel placed;
    // The width turns about +y by the twist: the blade faces the wind (Zhang Xia §3.2.5).
    placed.width_dir = across * pose.twist_cs.x - normal_dir * pose.twist_cs.y;
    placed.width = blade.width * lod_scale.x * lod_scale.y;
    placed.centre = blade.position + across * local.x + vec3(0.0, local.y, 0.0) + normal_dir * local.z;
    placed.tangent = across * pose.tangent.x + vec3(0.0, pose.tangent.y, 0.0) + normal_dir * pose.tangent.z;
    return placed;
}

// With FLAG_SOLID_OUTLINE: the part of a level's width at height t the alpha-tested outline
// covers (`scene::alpha`: half_width less the cutoff's inset), drawn as geometry so the far
// buckets need no texture or discard; 1 otherwise. The width is concave in t and the strip joins
// its levels by straight edges, so a coarse strip is thinner than the outline (a one-segment
// blade's triangle covers 59 % of it): STRIP_AREA widens it back to the outline's area
// (`scene::alpha::strip_area_scale`), the coverage a far blade a pixel or less across shows.
float outline_width(float t) {
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) == 0u) {
        return 1.0;
    }
    return max(2.0 * (outline_half_width(t) - SOLID_INSET), 0.0) * STRIP_AREA;
}

// Debug view `lod`: one colour per segment count.
vec3 lod_color(uint segments) {
    const vec3 colors[5] = vec3[5](vec3(0.9, 0.1, 0.1), vec3(0.95, 0.6, 0.05), vec3(0.9, 0.9, 0.1),
        vec3(0.1, 0.7, 0.2), vec3(0.1, 0.4, 0.9));
    return colors[min(findMSB(max(segments, 1u)), 4)];
}

// The terrain's normal under the blade's root (Belyaev §2.3's N_L).
vec3 blade_terrain_normal(BladeInstance blade) {
    return ground_normal(blade.position.xz);
}

// A blade's diffuse colour at height t (thesis 4.1: darker at the root, brighter towards the
// tip), from its variation's hue and brightness strayed from their means by `spread` (1: the
// blade's own; the far field's atlas bakes it, `shaders/far_field/atlas_bake.frag`).
vec3 blade_diffuse(uint variation, float t, float spread) {
    float hue = 0.5 + (unpack_variation(variation, 0) - 0.5) * spread;
    float brightness = 0.75 + 0.5 * (0.5 + (unpack_variation(variation, 1) - 0.5) * spread);
    vec3 root_color = mix(vec3(0.045, 0.12, 0.02), vec3(0.08, 0.13, 0.02), hue);
    vec3 tip_color = mix(vec3(0.22, 0.42, 0.06), vec3(0.42, 0.45, 0.10), hue);
    return mix(root_color, tip_color, t) * brightness;
}

// The colour at height t of `blade` (a strip of `segments` segments) at `world`, its width along
// `width_dir` and its centre line along `world_tangent`, under force `force_magnitude`: rgb the
// lit colour times the fog's transmittance, a the transmittance (blade.frag adds the sky's part).
// `terrain_normal`: `blade_terrain_normal` (per blade; unused by the debug views but fresnel).
// `represents`: the blades this one stands for, its widening by the density LOD (1 without).
vec4 shade_blade(BladeInstance blade, float t, vec3 world, vec3 width_dir, vec3 world_tangent,
    float force_magnitude, uint segments, vec3 terrain_normal, float represents) {
    // Diffuse colour, darker at the root and brighter towards the tip (thesis 4.1). A blade the
    // density LOD widened covers for `represents` blades, whose hues and brightnesses would have
    // averaged out over its area: its own stray from the mean by 1/sqrt(represents), the spread of
    // such a mean, so a thinned patch keeps the whole patch's average colour and its variation.
    vec3 diffuse = blade_diffuse(blade.variation, t, inversesqrt(max(represents, 1.0)));
    if ((RENDER_FLAGS & FLAG_DEBUG_FORCE) != 0u) {
        // Debug view: force magnitude from green (none) to red (the table's strongest pose).
        diffuse = mix(vec3(0.05, 0.25, 0.03), vec3(0.8, 0.02, 0.01), clamp(force_magnitude, 0.0, 1.0)) * mix(0.6, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_LOD) != 0u) {
        diffuse = lod_color(segments) * mix(0.4, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_TILES) != 0u) {
        // A colour per tile of the cull (`scene::tiles`), from a hash of its cell.
        uvec2 cell = uvec2(max((blade.position.xz - vec2(frame_values.tile_grid.x)) / frame_values.tile_grid.y, vec2(0.0)));
        uint h = (cell.x * 73856093u) ^ (cell.y * 19349663u);
        h = (h ^ (h >> 13)) * 0x5bd1e995u;
        diffuse = (0.15 + 0.6 * vec3(h & 255u, (h >> 8) & 255u, (h >> 16) & 255u) / 255.0) * mix(0.5, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_COVER) != 0u) {
        diffuse = cover_debug_color(ground_cover(blade.position.xz)) * mix(0.5, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_PRESSED) != 0u) {
        // The push-out pass left the pressed map's share in the force channel (push_out.comp).
        diffuse = mix(vec3(0.05, 0.3, 0.04), vec3(0.85, 0.05, 0.75), clamp(force_magnitude, 0.0, 1.0)) * mix(0.5, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_FAR) != 0u) {
        // The far field's band (`render::far_field`): the blades there thin out by the cull's dither.
        float band_start = uintBitsToFloat(frame_values.params.z);
        float d = length(blade.position - frame_values.band_eye.xyz);
        bool band = band_start > 0.0 && d > band_start;
        diffuse = (band ? vec3(0.85, 0.45, 0.05) : vec3(0.05, 0.45, 0.4)) * mix(0.5, 1.0, t);
    }
    if ((RENDER_FLAGS & FLAG_DEBUG_PATCHES) != 0u) {
        // The patch pass left the chain's share in the force channel, 0 elsewhere (patch.comp).
        diffuse = mix(vec3(0.12, 0.2, 0.1), vec3(0.95, 0.45, 0.02), clamp(force_magnitude, 0.0, 1.0)) * mix(0.5, 1.0, t);
    }
    // Two-sided: light the side facing the viewer, decided from the view vector so the strip's
    // triangle parity cannot flip it. Belyaev §2.3 is linear in the diffuse colour, and so is the
    // fog: colour = lit * rim + sky * (1 - fog) in blade.frag.
    vec3 n = normalize(cross(width_dir, world_tangent));
    n = dot(n, frame_values.camera_position.xyz - world) < 0.0 ? -n : n;
    // The haze of a block field's last fifth (the frame's params.w: its view distance), as the
    // ground's: blades to the view distance end in it with the ground, not at a line.
    float fog = fog_transmittance(world, frame_values.camera_position, frame_values.sky_color)
        * horizon_haze(length(world - frame_values.camera_position.xyz), uintBitsToFloat(frame_values.params.w));
    float l6 = height_six(t, segments, MODEL_SEGMENTS);
    if ((RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u) {
        // The strip's colour is linear between levels over its straight-edged width, where brute
        // force's is over the outline's: STRIP_L6 gives the strip brute force's area-weighted
        // mean of l^6 (`scene::alpha::strip_l6_scale`; the 2-segment bucket was 26 % over it and
        // the 1M field's horizon up to 0.7 % brighter than brute force).
        l6 *= STRIP_L6;
    }
    vec3 lit = blade_radiance_l6(diffuse, diffuse, n, frame_values.sun_direction.xyz, t, l6);
    if ((RENDER_FLAGS & (FLAG_DEBUG_FORCE | FLAG_DEBUG_LOD | FLAG_DEBUG_TILES | FLAG_DEBUG_COVER | FLAG_DEBUG_PRESSED | FLAG_DEBUG_PATCHES | FLAG_DEBUG_FAR)) == 0u) {
        // Belyaev §2.3's Fresnel term on contour areas, over the terrain normal under the root.
        vec3 fresnel = blade_fresnel_l6(terrain_normal, normalize(frame_values.camera_position.xyz - world), l6);
        lit = lit + fresnel;
        if ((RENDER_FLAGS & FLAG_DEBUG_FRESNEL) != 0u) {
            lit = fresnel; // the term alone, unfogged
            fog = 1.0;
        }
    }
    return vec4(lit * fog, fog);
}

#endif
