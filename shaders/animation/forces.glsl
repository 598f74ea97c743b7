// The external force on a blade (thesis 3.2.2, 4.5): corner forces interpolated with the blade's
// precomputed weights (eq. 3.6/3.8), plus, with delayed attenuation, every point source (eq. 4.1)
// and collider evaluated at the blade itself. Mirrors `render::animation::blade_force` on the CPU.
#ifndef MEADOW_FORCES_GLSL
#define MEADOW_FORCES_GLSL

const float MIN_SOURCE_DISTANCE = 0.05; // wind::MIN_SOURCE_DISTANCE
const float COLLIDER_PUSH = 1.2;        // wind::COLLIDER_PUSH
const float COLLIDER_SIGMA = 3.0;       // wind::COLLIDER_SIGMA

vec2 source_force(vec2 w, float power, float sigma, vec2 p) {
    vec2 wp = p - w;
    float d = length(wp);
    if (d < 1e-6) {
        return vec2(0.0);
    }
    return wp / d * power / pow(max(d, MIN_SOURCE_DISTANCE), sigma);
}

vec2 collider_force(vec2 center, vec2 radii, vec2 p) {
    vec2 q = (p - center) / radii;
    float d = length(q);
    if (d < 1e-6) {
        return vec2(0.0);
    }
    return normalize(q / radii) * COLLIDER_PUSH / pow(max(d, 1.0), COLLIDER_SIGMA);
}

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

vec2 blade_force(uint blade_index, vec2 root) {
    uint n = frame.keyframes.w;
    vec4 w;
    BladeCluster c;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        c = field_cluster(root, w);
    } else {
        c.corner = clusters[blade_index].corner;
        w = unpackUnorm4x8(clusters[blade_index].weights);
    }
    vec4 f = corners[c.corner] * w.x + corners[c.corner + 1u] * w.y + corners[c.corner + n] * w.z
        + corners[c.corner + n + 1u] * w.w;
    vec2 force = f.xy;
    if (ATTENUATION == ATTENUATION_BLADE) {
        float exposure = f.z;
        uint sources = frame.keyframes.z;
        for (uint s = 0u; s < sources; ++s) {
            vec4 e = emitters[s];
            force += exposure * source_force(e.xy, e.z, e.w, root);
        }
        for (uint i = sources; i < sources + frame.keyframe_shape.y; ++i) {
            vec4 e = emitters[i];
            force += collider_force(e.xy, e.zw, root);
        }
    }
    return force;
}

#endif
