#version 460
#extension GL_GOOGLE_include_directive : require
// Pelzer's sine animation (GPU Gems ch. 7, §7.4), a blade response (`render::animation::sine`),
// once per blade into the renderer's pose records. Pelzer moves a grass object's upper vertices by
// a translation vector (Listings 7-2 to 7-4: position + translation, normal · height +
// translation) and leaves its `CalcTranslation` open. meadow's, in blade heights:
//   T(p) = clamp_length(g·w + a·|w|·sin θ(p)·ŵ, MOST) = ŵ·clamp(|w|·(g + a·sin θ(p)), ±MOST)
//   θ(p) = ω·t − κ·d̂·p   (a sine wave running along the global wind's direction d̂)
// with w the wind at the blade's root (m/s, horizontal): the wind field's (wind/wind_field.glsl)
// plus each collider's push as a local wind (thesis 5.2; animation/forces.glsl's reach-weighted
// force, in m/s through wind::KEYFRAME_WIND_SCALE), ŵ its direction, g the lean per m/s and a the sway's share of it (a < g: under a wind the tips
// always lean downwind). Model level m, at height fraction s = m / MODEL_SEGMENTS of the neutral
// blade, moves horizontally by Δ_m = T(p_m) · s² · height (Pelzer's upper vertices move, the root
// does not; the s² profile bends the segmented blade smoothly between the two). The variants
// differ only in where the phase is taken, p_m:
//   - per object (§7.4.4, this build): p_m = the blade's root for every level, one T per blade;
//   - per vertex (§7.4.3, the variant `vertex`): p_m = the level's rest point in the world, so two
//     blades at one place move alike and one blade's levels sway with the phases of their own
//     positions;
//   - per cluster (§7.4.2, the variant `cluster`): p_m = the centre of the blade's tile of the cull
//     (a block field's cell), so every blade of a tile sways in phase, as Pelzer's clusters do
//     with one draw each. With the cull the blade class then draws one row per visible tile
//     (cull/tile_rows.glsl); the phase is the tile's whichever way the tile is drawn.
// The tangent is the derivative along the blade, dP/ds + 2·s·height·T (the phase's change along
// a per-vertex blade is left out of it: it only lights the level), so only the levels the LOD
// bucket reads are evaluated.
// Under no wind T = 0: the neutral blade. Phases are world-exact: the host folds ω·t − κ·d̂·O in
// f64 into `wave.z`, and p is relative to O here.
// variant vertex: SINE_PER_VERTEX
// variant cluster: SINE_PER_TILE
#define POSE_WRITER
#include "common/bindings.glsl"
#include "common/bezier.glsl"
#include "animation/forces.glsl"
#include "animation/pose_write.glsl"

layout(local_size_x = POSE_GROUP) in;

// The response's block in its pass's own set (`Draws` is binding 0 there), one per frame in flight.
layout(set = SET_PASS, binding = 1, std140) uniform SineShape {
    vec4 gains; // x g (heights per m/s), y a (heights per m/s), z MOST (heights), w κ (rad/m)
    vec4 wave;  // xy d̂ (x, z), z ω·t − κ·d̂·O mod 2π, w unused
} sine;

// T = g·w + a·|w|·sin θ·ŵ = ŵ·|w|·(g + a·sin θ): T lies along the wind, so only its signed length
// depends on the phase. That length at phase θ under a wind of `speed` m/s, clamped to MOST.
float sway(float theta, float speed) {
    float reach = speed * (sine.gains.x + sine.gains.y * sin(theta));
    return clamp(reach, -sine.gains.z, sine.gains.z);
}

// θ at the phase point `p` (relative to O).
float phase_at(vec2 p) {
    return sine.wave.z - sine.gains.w * dot(sine.wave.xy, p);
}

#ifdef SINE_PER_TILE
// The centre of the tile a blade belongs to (relative to O): a block field's cell, from the
// entry's ring slot (`visible_blade`, cull.glsl); a stored field's tile of the tile grid under its
// root (`scene::tiles::TileGrid::cell`, clamped to the grid).
vec2 tile_centre(uvec2 entry, BladeInstance blade) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        return (vec2(ring_cell(entry.x >> 16)) + 0.5) * frame_values.field.x;
    }
    float origin = frame_values.tile_grid.x;
    float size = frame_values.tile_grid.y;
    vec2 cell = clamp(floor((blade.position.xz - vec2(origin)) / size), vec2(0.0), vec2(float(frame.cull_tiles.x) - 1.0));
    return vec2(origin) + (cell + 0.5) * size;
}
#endif

void main() {
    uint i;
    uvec2 entry;
    BladeInstance blade;
    uint blade_index;
    if (!posed_blade(i, entry, blade, blade_index)) {
        return;
    }
    vec2 w = blade_force(blade_index, blade) * KEYFRAME_WIND_SCALE;
    float speed = length(w);
    vec2 along = speed > 0.0 ? w / speed : vec2(0.0);
    vec3 p[4];
    neutral_control_points(blade.height, unpack_variation(blade.variation, 2), p);
    // The blade's frame in the world (place_level: x across, z along the normal).
    vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
    vec2 normal_dir = vec2(sin(blade.facing), cos(blade.facing));
#ifdef SINE_PER_TILE
    vec2 t = along * sway(phase_at(tile_centre(entry, blade)), speed);
#elif defined(SINE_PER_VERTEX)
    // θ at a level's rest point root + across·x + normal·z: θ(root) less its slope along the
    // blade's frame, taken once per blade.
    float theta = phase_at(blade.position.xz);
    vec2 slope = sine.gains.w * vec2(dot(sine.wave.xy, across), dot(sine.wave.xy, normal_dir));
#else
    vec2 t = along * sway(phase_at(blade.position.xz), speed);
#endif
    float inv = 1.0 / (POSE_SCALE * max(blade.height, 1e-6));
    uint base = pose_base(i);
    for (uint level = 0u; level <= MODEL_SEGMENTS; level++) {
        if (!level_read(level)) {
            continue;
        }
        float s = float(level) / float(MODEL_SEGMENTS);
        vec3 rest = bezier_point(p[0], p[1], p[2], p[3], s);
#ifdef SINE_PER_VERTEX
        vec2 t = along * sway(theta - dot(slope, rest.xz), speed);
#endif
        // Into the blade's frame, in metres: the displacement and its derivative along s.
        vec2 d = t * (s * s * blade.height);
        vec2 dd = t * (2.0 * s * blade.height);
        vec3 point = rest + vec3(dot(d, across), 0.0, dot(d, normal_dir));
        vec3 tangent = bezier_tangent(p[0], p[1], p[2], p[3], s) + vec3(dot(dd, across), 0.0, dot(dd, normal_dir));
        tangent = length(tangent) > 0.0 ? normalize(tangent) : vec3(0.0, 1.0, 0.0);
        write_pose_level(base, level, point * inv, tangent, vec2(1.0, 0.0), length(t) / sine.gains.z);
    }
}
