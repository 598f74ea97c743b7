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

// A block field's blade has no stored cluster record (its block is placed in every cell): the
// corner and the bilinear weights of eq. 3.7 from its position in the grid of corners around O,
// `scene::clusters::ClusterGrid::locate` unquantised.
BladeCluster field_cluster(vec2 root, out vec4 w) {
    uint n = frame.keyframes.w;
    float size = frame.terrain.y;
    vec2 g = clamp((root - frame.field.zw) / size, vec2(0.0), vec2(float(n - 1u)));
    uvec2 c = min(uvec2(g), uvec2(n - 2u));
    vec2 f = g - vec2(c);
    w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    BladeCluster record;
    record.corner = c.y * n + c.x;
    record.weights = 0u;
    return record;
}

// The field at cluster corner `index`: velocity (m/s) and exposure.
vec4 wind_corner(uint index) {
    return corners[index];
}

// The wind at a blade (`blade_index`, root `root` relative to O): velocity in m/s and the
// exposure interpolated from the corners.
vec4 wind_at_blade(uint blade_index, vec2 root) {
    uint n = frame.keyframes.w;
    vec4 w;
    BladeCluster c;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        c = field_cluster(root, w);
    } else {
        c.corner = clusters[blade_index].corner;
        w = unpackUnorm4x8(clusters[blade_index].weights);
    }
    // Eq. 3.6 / 3.8.
    vec4 f = wind_corner(c.corner) * w.x + wind_corner(c.corner + 1u) * w.y + wind_corner(c.corner + n) * w.z
        + wind_corner(c.corner + n + 1u) * w.w;
    vec2 wind = f.xz;
    if (ATTENUATION == ATTENUATION_BLADE) {
        // Delayed attenuation (4.5): the sources at the blade itself.
        float exposure = f.w;
        for (uint s = 0u; s < frame.keyframes.z; ++s) {
            vec4 e = emitters[s];
            wind += exposure * source_wind(e.xy, e.z, e.w, root);
        }
    }
    return vec4(wind.x, f.y, wind.y, f.w);
}

#endif
