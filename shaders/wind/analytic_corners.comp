#version 460
#extension GL_GOOGLE_include_directive : require
// The analytic wind field on the GPU (`render::wind::analytic`): the wind velocity (m/s) and the
// calm-area exposure at every cluster corner of this frame (thesis 3.2.2), at every level (a
// block field's WIND_LEVELS nested levels, `render::field_gpu::wind_level`), each step, instead of
// the thesis' CPU loop. The global wind with gusts, taken relative to the frame's O with its
// waves' phases at O computed in f64 on the CPU (so 100 km out is as exact as the origin), calm
// areas (thesis 5.1: no wind inside), and with cluster attenuation the point sources (eq. 4.1);
// with delayed attenuation (4.5) the corners carry the global wind and the exposure only, and the
// blades add the sources themselves (`wind/wind_field.glsl`). Colliders are not in the field: the
// blades take their shapes (thesis 5.2 in 3-D, `animation/forces.glsl`).
// The CPU mirror is `render::animation::corner_forces_at`, its f64 reference
// `wind::Wind::corner_velocity_f64`. Its own set (no scene sets): the parameters, this frame's
// emitters and this frame's corners.
// The variant `perlin` (PERLIN_WIND) is Belyaev's Perlin field (`render::wind::perlin`,
// wind/perlin.glsl): the noise's layers in place of the global wind and its gusts, the noise in
// binding 4; sources and calm areas as here.
// variant perlin: PERLIN_WIND
#include "common/shared.glsl"
#include "wind/analytic.glsl"

layout(local_size_x = WIND_GROUP) in;

// `render::wind::params::Params`, one block bound twice: its values as a uniform block (one load
// for every lane on llvmpipe, where a storage load is a loop over the lanes), its counts and
// flags, which decide control flow, through a storage binding (the lavapipe profile's rule,
// common/profile.glsl).
#define WIND_PARAMS \
    vec4 global;   /* direction x, z; mean speed (m/s); 0 without a global wind, 1 steady, 2 gusts */ \
    vec4 phases;   /* the four waves' phases at O at the frame's time, in [0, 2π) */ \
    vec4 waves01;  /* waves 0 and 1: wave vectors (x, z) in rad/m */ \
    vec4 waves23;  /* waves 2 and 3 */ \
    vec4 grid;     /* the first corner relative to O (x, z), the cluster edge, 0 */ \
    uvec4 shape;   /* corners per side of a level, corners of every level, 1 with delayed attenuation, levels */ \
    uvec4 counts;  /* sources, colliders (not read here: the blades take them), calm areas, 0 */ \
    vec4 levels[WIND_LEVELS]; /* per level: first corner relative to O (x, z), spacing, 0 */ \
    vec4 calm[MAX_CALM_AREAS]; /* min x, z, max x, z relative to O */ \
    vec4 perlin[3];      /* the Perlin layers: offset at O (texels), c_i (texels/m), k_i · speed (m/s) */ \
    vec4 perlin_dirs[3]; /* each layer's direction d_i (x, z) */ \
    uvec4 perlin_mips[WIND_LEVELS]; /* per level, each layer's mip of the noise */
layout(set = 0, binding = 0, std140) uniform WindValues { WIND_PARAMS } wind;
layout(set = 0, binding = 3, std430) readonly buffer WindControl { WIND_PARAMS } control;
// Point sources (x, z relative to O, power, sigma), then colliders (read by the blades).
layout(set = 0, binding = 1, std430) readonly buffer Emitters { vec4 emitters[]; };
// This frame's corners: velocity (x, y, z) in m/s, exposure.
layout(set = 0, binding = 2, std430) writeonly buffer Corners { vec4 corners[]; };
#ifdef PERLIN_WIND
// The Perlin field's noise and its mips, RG32F texels (`render::wind::perlin::Noise`).
layout(set = 0, binding = 4) uniform samplerBuffer noise_texels;
#include "wind/perlin.glsl"
#endif

float exposure_at(vec2 q) {
    for (uint i = 0u; i < control.counts.z; ++i) {
        vec4 c = wind.calm[i];
        if (all(greaterThanEqual(q, c.xy)) && all(lessThanEqual(q, c.zw))) {
            return 0.0;
        }
    }
    return 1.0;
}

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= control.shape.y) {
        return;
    }
    uint n = wind.shape.x;
    // The level's corner (innermost level first, n² corners each), as
    // `scene::clusters::ClusterGrid::corner_position` on `render::field_gpu::wind_level`.
    uint level = index / (n * n);
    uint local = index % (n * n);
    vec4 g = wind.levels[level];
    vec2 q = vec2(g.x + float(local % n) * g.z, g.y + float(local / n) * g.z);
    float exposure = exposure_at(q);
    vec2 v = vec2(0.0);
    float global = control.global.w;
    if (global > 0.5) {
        v = global_wind(wind.global.xy, wind.global.z, global > 1.5, wind.phases, wind.waves01, wind.waves23, q);
    }
#ifdef PERLIN_WIND
    v += perlin_wind(q, level);
#endif
    if (control.shape.z == 0u) {
        for (uint s = 0u; s < control.counts.x; ++s) {
            vec4 e = emitters[s];
            v += source_wind(e.xy, e.z, e.w, q);
        }
    }
    // Calm areas block the wind (thesis 5.1).
    vec2 f = v * exposure;
    // A non-finite wind (an overflowing eq. 4.1) would select an undefined pose: none.
    if (any(isnan(f)) || any(isinf(f))) {
        f = vec2(0.0);
    }
    corners[index] = vec4(f.x, 0.0, f.y, exposure);
}
