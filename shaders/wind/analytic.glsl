// The analytic wind field's terms (`render::wind::analytic`), in m/s: the global wind with gusts
// and point sources (thesis eq. 4.1); colliders are not wind (the blade responses take their
// shapes, `animation/forces.glsl`). Shared by
// the pass that evaluates the field at the cluster corners (`wind/analytic_corners.comp`) and by
// the per-blade sampling of delayed attenuation (`wind/wind_field.glsl`, thesis 4.5). Mirrors
// `wind::GlobalWind::force` and `wind::PointSource::force_from` on the CPU, times `wind::KEYFRAME_WIND_SCALE`.
#ifndef MEADOW_WIND_ANALYTIC_GLSL
#define MEADOW_WIND_ANALYTIC_GLSL

const float KEYFRAME_WIND_SCALE = 8.0;  // wind::KEYFRAME_WIND_SCALE: m/s per keyframe force unit
const float MIN_SOURCE_DISTANCE = 0.05; // wind::MIN_SOURCE_DISTANCE

// Eq. 4.1: wind = normalise(WP) · ω / |WP|^σ for a source at `w` of power ω (keyframe units)
// and concentration σ, in m/s.
vec2 source_wind(vec2 w, float power, float sigma, vec2 p) {
    vec2 wp = p - w;
    float d = length(wp);
    if (d < 1e-6) {
        return vec2(0.0);
    }
    return wp / d * power / pow(max(d, MIN_SOURCE_DISTANCE), sigma) * KEYFRAME_WIND_SCALE;
}

// The global wind at `q` (relative to O) in m/s: `direction` the unit direction it blows
// towards, `speed` its mean in m/s, `phases` the four waves' phases at O and this frame's time
// (taken in f64 on the CPU, `wind::GlobalWind::phases`), `waves` their wave vectors
// (two per vec4). Three gust fronts along and slightly across the wind scale it, a fourth wave
// swirls its direction (`wind::GlobalWind::force`).
vec2 global_wind(vec2 direction, float speed, bool gusts, vec4 phases, vec4 waves01, vec4 waves23, vec2 q) {
    if (!gusts) {
        return direction * speed;
    }
    vec4 theta = phases + vec4(dot(waves01.xy, q), dot(waves01.zw, q), dot(waves23.xy, q), dot(waves23.zw, q));
    vec4 s = sin(theta);
    float gust = 0.55 * s.x + 0.30 * s.y + 0.15 * s.z;
    float swirl = 0.12 * s.w;
    vec2 d = normalize(vec2(direction.x - swirl * direction.y, direction.y + swirl * direction.x));
    return d * speed * (1.0 + 0.45 * gust);
}

#endif
