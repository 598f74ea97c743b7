#version 460
#extension GL_GOOGLE_include_directive : require
// Blades by vertex pulling: no vertex buffer. Each instance draws BLADES_PER_INSTANCE blades as one
// triangle strip; gl_InstanceIndex and gl_VertexIndex select the blade and its strip vertex.
// Strip vertex 2k + side lies on Bézier spline `side` at t = k / segments (thesis 4.1). Blades in
// an instance are joined by repeating their first and last vertices (degenerate triangles), see
// `scene::bezier::Batching`.
//
// The variant `keyframes` (PER_VERTEX_KEYFRAMES) is the keyframe response's per-vertex path (a
// per-vertex `render::animation::response::BladeInput`), its tables in this pass's own set
// (animation/keyframes.glsl); the shader itself draws neutral blades or reads pose records
// (`SET_POSES`).
// variant keyframes: PER_VERTEX_KEYFRAMES
//
// The variant `tiles` (TILE_ROWS) draws the blade class's per-tile rows (cull/tile_rows.glsl):
// one draw per visible tile and LOD bucket, its record found by gl_DrawID.
// variant tiles: TILE_ROWS
//
// Texture mode (thesis 4.4.1): the blade's force is interpolated from its cluster's corners
// (eq. 3.6), expressed in the blade's frame, and selects a pose of the keyframe texture; the
// pose's displacement (eq. 3.4/3.9), scaled by the blade's height, is added to the neutral
// Bézier blade, and the width turns by the pose's twist.
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "blades/blade_place.glsl"
#ifdef PER_VERTEX_KEYFRAMES
#include "animation/forces.glsl"
#include "animation/keyframes.glsl"
#include "blades/blade_select.glsl"
#endif
#ifdef TILE_ROWS
#include "cull/tile_rows.glsl"
// The cull's per-tile rows, in this pass's own set (`render::passes::blades`).
layout(set = SET_PASS, binding = 0, std430) readonly buffer TileRows { uint tile_rows[]; };
#endif

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

// The solid outline's rim darkening over a one-segment blade's triangle, fitted affine in t (root,
// tip): the one-segment bucket's fragment shader computes no rim (blade_shading.glsl).
const float ONE_SEGMENT_SHADE_ROOT = 1.0027; // scene::alpha::ONE_SEGMENT_SHADE_ROOT
const float ONE_SEGMENT_SHADE_TIP = 0.7780; // scene::alpha::ONE_SEGMENT_SHADE_TIP

// The rim's fit at height t for the one-segment bucket's solid outline, 1 otherwise.
float bucket_shade(float t) {
    bool fitted = (RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u && SEGMENTS == 1u;
    return fitted ? mix(ONE_SEGMENT_SHADE_ROOT, ONE_SEGMENT_SHADE_TIP, t) : 1.0;
}

#ifdef PER_VERTEX_KEYFRAMES
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
// level * MODEL_SEGMENTS / SEGMENTS (`model_level`), between two stored levels when SEGMENTS does
// not divide MODEL_SEGMENTS (a constant test: the interpolation compiles out otherwise). The
// fewer-segment blade samples the same curve.
LevelPose animated(uint blade_index, BladeInstance blade, vec3 p[4], uint level, float t) {
    float frac;
    uint m0 = model_level(level, SEGMENTS, frac);
    uint m1 = min(m0 + 1u, MODEL_SEGMENTS);
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
        if (frac > 0.0) {
            LevelPose next = pose_levels(p, sel, blade.height, m1);
            pose.local = mix(pose.local, next.local, frac);
            pose.tangent = mix(pose.tangent, next.tangent, frac);
            pose.twist_cs = normalize(mix(pose.twist_cs, next.twist_cs, frac));
        }
    }
    pose.force = force;
    return pose;
}
#endif

void main() {
    const uint segments = SEGMENTS;
    uint blade_index = uint(gl_InstanceIndex) * BLADES_PER_INSTANCE + uint(gl_VertexIndex) / STRIP_STRIDE;
    // The cull's fade (the density LOD is about to drop the blade) and widening (its neighbours
    // were dropped): Belyaev §2.2 smooth transitions.
    vec2 lod_scale = vec2(1.0);
    // Where `--eval blade`'s pose record (and with the cull the placed levels) is: by blade, or
    // with the cull by visible entry (the blade-pose pass evaluates only the drawn blades).
    uint record = blade_index;
    uvec2 entry = uvec2(0u);
    bool tail = BLADES_PER_INSTANCE > 1u && blade_index >= frame.params.y;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        // Entry `blade_index` of the cull's list (instance * BLADES_PER_INSTANCE + k, the
        // bucket's first instance counting from its base); a bucket's last instance ends in
        // VISIBLE_PADDING.
        entry = visible_entry(blade_index);
        tail = entry.x == VISIBLE_PADDING;
#ifdef TILE_ROWS
        // This draw's tile (its row, by gl_DrawID): the entries of the instances it shares with
        // the tiles before and after it are theirs to draw.
        uint row = tile_record_word(LOD_BUCKET, uint(gl_DrawID));
        tail = tail || blade_index < tile_rows[row] || blade_index >= tile_rows[row + 1u];
#endif
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
    uint level = strip >> 1;
    float side = float(strip & 1u);
    float t = float(level) / float(segments);
    out_uv = vec2(side, t);
    out_u_center = side;
    vec3 world;
    if ((RENDER_FLAGS & FLAG_LEVELS) != 0u) {
        // Placed and lit once per level by blade_levels.comp: widen and project.
        uint at = (record * (MODEL_SEGMENTS + 1u) + level) * LEVEL_UVEC2S;
        uvec2 a = level_word(at);
        uvec2 b = level_word(at + 1u);
        uvec2 c = level_word(at + 2u);
        vec2 across = unpackHalf2x16(b.y);
        world = vec3(uintBitsToFloat(a), uintBitsToFloat(b.x))
            + vec3(across.x, 0.0, across.y) * ((side - 0.5) * outline_width(t));
        out_lit = vec4(unpackHalf2x16(c.x), unpackHalf2x16(c.y));
        out_lit.rgb *= bucket_shade(t);
        gl_Position = frame.view_proj * vec4(world, 1.0);
        return;
    }
    BladeInstance blade;
    if ((RENDER_FLAGS & FLAG_CULLED) != 0u) {
        blade = visible_instance(entry, blade_index);
    } else {
        blade = blade_record(blade_index);
    }
    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    LevelPose pose;
    if ((RENDER_FLAGS & FLAG_EVAL_BLADE) != 0u) {
        // A response's pose records.
        pose = recorded_level(record, blade.height, level, SEGMENTS);
    } else {
#ifdef PER_VERTEX_KEYFRAMES
        pose = animated(blade_index, blade, p, level, t);
#else
        pose.local = bezier_point(p[0], p[1], p[2], p[3], t);
        pose.tangent = bezier_tangent(p[0], p[1], p[2], p[3], t);
        pose.twist_cs = vec2(1.0, 0.0);
        pose.force = 0.0;
#endif
    }
    PlacedLevel placed = place_level(blade, pose, lod_scale);
    world = placed.centre + placed.width_dir * ((side - 0.5) * placed.width * outline_width(t));
    out_lit = shade_blade(blade, t, world, placed.width_dir, placed.tangent, pose.force, SEGMENTS,
        blade_terrain_normal(blade), lod_scale.y);
    out_lit.rgb *= bucket_shade(t);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
