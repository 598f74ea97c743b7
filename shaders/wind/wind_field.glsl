// Sampling the wind field (`render::wind`): the one include every blade response reads the wind
// through (the keyframes' `animation/forces.glsl` today; flowers and the far field later). The
// field's quantity is the wind velocity in m/s (x, y, z) and the calm-area exposure (thesis 4.5).
// The analytic field writes it at the cluster corners (`wind/analytic_corners.comp` on the GPU,
// `render::animation::corner_forces_at` on the CPU with --brute-force, as the thesis did); a
// blade takes the corners' wind weighted by its precomputed weights (eq. 3.6/3.8), plus, with
// delayed attenuation, every point source (eq. 4.1) evaluated at the blade itself. Colliders are
// not wind: each response takes their shapes from `emitters` (the keyframes: `collider_force` of
// `animation/forces.glsl`). Mirrored on the CPU by `render::animation::blade_wind`. The includer
// declares `frame`, `clusters`, `corners` (vec4: velocity xyz, exposure) and `emitters` (sources,
// then colliders, relative to O).
#ifndef MEADOW_WIND_FIELD_GLSL
#define MEADOW_WIND_FIELD_GLSL
#include "wind/analytic.glsl"

// A block field's wind lives in nested levels around O's cell (at most WIND_LEVELS)
// (`render::field_gpu::wind_level`): level l has WIND_LEVEL_CLUSTERS clusters per side of 2^l cluster edges, about the same centre, its
// corners after the n² of each level inside it. The corner and the bilinear weights of eq. 3.7 of a
// point in level `level`, clamped to it: `scene::clusters::ClusterGrid::locate` unquantised.
BladeCluster level_cluster(uint level, vec2 root, out vec4 w) {
    uint n = frame.wind_counts.z;
    float size = frame.terrain.y * float(1u << level);
    float first = 0.5 * frame.field.x - 0.5 * float(WIND_LEVEL_CLUSTERS) * size;
    vec2 g = clamp((root - vec2(first)) / size, vec2(0.0), vec2(float(n - 1u)));
    uvec2 c = min(uvec2(g), uvec2(n - 2u));
    vec2 f = g - vec2(c);
    w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    BladeCluster record;
    record.corner = level * n * n + c.y * n + c.x;
    record.weights = 0u;
    return record;
}

// The field at cluster corner `index`: velocity (m/s) and exposure.
vec4 wind_corner(uint index) {
    return corners[index];
}

// Eq. 3.6 / 3.8: the corners' wind weighted.
vec4 interpolated_wind(BladeCluster c, vec4 w) {
    uint n = frame.wind_counts.z;
    return wind_corner(c.corner) * w.x + wind_corner(c.corner + 1u) * w.y + wind_corner(c.corner + n) * w.z
        + wind_corner(c.corner + n + 1u) * w.w;
}

// The finest level of a block field's wind that holds `root` (relative to O), and how far it is
// blended into the next (0 to 1, over the outer quarter of the level's half-extent, so no seam
// shows where the levels meet; 0 at the last level). The field holds the levels its plants reach
// (`frame.wind_counts.w`, `render::field_gpu::wind_levels`); past the last the wind is its edge's.
uint wind_level_at(vec2 root, out float blend) {
    uint levels = max(frame.wind_counts.w, 1u);
    float half0 = 0.5 * float(WIND_LEVEL_CLUSTERS) * frame.terrain.y;
    vec2 from_centre = abs(root - vec2(0.5 * frame.field.x));
    float ratio = max(from_centre.x, from_centre.y) / half0;
    uint level = ratio <= 1.0 ? 0u : min(uint(ceil(log2(ratio))), levels - 1u);
    blend = level + 1u < levels ? clamp((ratio / float(1u << level) - 0.75) * 4.0, 0.0, 1.0) : 0.0;
    return level;
}

// A block field's wind at `root` (relative to O): the finest level that holds it, blended into the
// next (`wind_level_at`).
vec4 levels_wind(vec2 root) {
    float blend;
    uint level = wind_level_at(root, blend);
    vec4 w;
    BladeCluster c = level_cluster(level, root, w);
    vec4 f = interpolated_wind(c, w);
    if (blend > 0.0) {
        c = level_cluster(level + 1u, root, w);
        f = mix(f, interpolated_wind(c, w), blend);
    }
    return f;
}

// The field `f` the corners give at `p` (relative to O), with delayed attenuation (4.5) plus every
// point source evaluated at `p` itself, scaled by the exposure there.
vec4 with_point_sources(vec4 f, vec2 p) {
    vec2 wind = f.xz;
    if (ATTENUATION == ATTENUATION_BLADE) {
        float exposure = f.w;
        for (uint s = 0u; s < frame.wind_counts.x; ++s) {
            vec4 e = emitters[s];
            wind += exposure * source_wind(e.xy, e.z, e.w, p);
        }
    }
    return vec4(wind.x, f.y, wind.y, f.w);
}

// The wind at a blade (`blade_index`, root `root` relative to O): velocity in m/s and the
// exposure interpolated from the corners.
vec4 wind_at_blade(uint blade_index, vec2 root) {
    vec4 f;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        f = levels_wind(root);
    } else {
        BladeCluster c;
        c.corner = clusters[blade_index].corner;
        f = interpolated_wind(c, unpackUnorm4x8(clusters[blade_index].weights));
    }
    return with_point_sources(f, root);
}

#endif
