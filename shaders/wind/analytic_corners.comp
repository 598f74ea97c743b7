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
// The variant `fluid` (FLUID_WIND) is the fluid wind (`render::wind::fluid`, wind/fluid.glsl): a
// corner inside its grid takes the grid's wind at the sample height above the ground, tri-linearly
// (Zhang Xia §3.2.2), blended into this analytic field over the grid's outer cells.
// variant perlin: PERLIN_WIND
// variant fluid: FLUID_WIND
#include "common/shared.glsl"
#include "wind/analytic.glsl"

layout(local_size_x = WIND_GROUP) in;

#include "wind/params.glsl"
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
#ifdef FLUID_WIND
// The fluid's velocities after this frame's step (`render::wind::fluid::pass`), GENERAL layout.
layout(set = 0, binding = 5, rgba32f) uniform readonly image3D Src;
// The upwind ghosts' analytic wind, from the same step (wind/fluid.glsl's `fluid_ring_texel`).
layout(set = 0, binding = 6, rgba32f) uniform readonly image3D Inflow;
#include "wind/fluid.glsl"

// The fluid's wind at corner `q` (relative to O) and its weight: 1 inside the grid, falling
// linearly to 0 over its outer `fluid_corner.w` cells, 0 past it.
vec4 fluid_wind_at(vec2 q) {
    vec3 h = wind.fluid_cell.xyz;
    vec2 n = vec2(wind.fluid_dims.xz);
    vec2 g = (q - wind.fluid_corner.xy) / h.xz; // in cells from the window's first corner
    vec2 edge = min(g, n - g);
    float weight = clamp(min(edge.x, edge.y) / wind.fluid_corner.w, 0.0, 1.0);
    if (weight <= 0.0) {
        return vec4(0.0);
    }
    vec3 v = fluid_sample(vec3(g.x - 0.5, wind.fluid_corner.z / h.y - 0.5, g.y - 0.5));
    return vec4(v, weight);
}
#endif

float exposure_at(vec2 q, uint calm) {
    for (uint i = 0u; i < calm; ++i) {
        vec4 c = wind.calm[i];
        if (all(greaterThanEqual(q, c.xy)) && all(lessThanEqual(q, c.zw))) {
            return 0.0;
        }
    }
    return 1.0;
}

void main() {
#ifdef FLUID_WIND
    fluid_load_control();
#endif
    // A row of workgroups per level (`render::wind::corners_pass`), so the level and all that
    // follows from it (its grid, the noise's mips) is the same across a workgroup.
    // The values its branches test, through storage (wind/params.glsl), each block in one load: on
    // llvmpipe a storage load is a loop over the lanes.
    uvec4 shape = control.shape;
    uvec4 counts = control.counts;
    uint n = shape.x;
    uint level = gl_WorkGroupID.y;
    uint local = gl_GlobalInvocationID.x;
    if (local >= n * n) {
        return;
    }
    // The level's corner (innermost level first, n² corners each), as
    // `scene::clusters::ClusterGrid::corner_position` on `render::field_gpu::wind_level`.
    uint index = level * n * n + local;
    vec4 g = wind.levels[level];
    vec2 q = vec2(g.x + float(local % n) * g.z, g.y + float(local / n) * g.z);
    float exposure = exposure_at(q, counts.z);
#ifdef PERLIN_WIND
    // The noise in place of the global wind and its gusts (`render::wind::perlin::fill_params`
    // leaves no global wind): not compiled in, since llvmpipe runs an `if`'s body under a lane
    // mask even when no lane takes it (the pass read 0.41-0.44 ms with it, 0.36 without).
    vec2 v = perlin_wind(q, level);
#else
    vec2 v = vec2(0.0);
    float global = control.global.w;
    if (global > 0.5) {
        v = global_wind(wind.global.xy, wind.global.z, global > 1.5, wind.phases, wind.waves01, wind.waves23, q);
    }
#endif
    if (shape.z == 0u) {
        for (uint s = 0u; s < counts.x; ++s) {
            vec4 e = emitters[s];
            v += source_wind(e.xy, e.z, e.w, q);
        }
    }
    // Calm areas block the wind (thesis 5.1).
    vec2 f = v * exposure;
    float up = 0.0;
#ifdef FLUID_WIND
    // The fluid damps its own calm areas.
    vec4 fluid = fluid_wind_at(q);
    f = mix(f, fluid.xz, fluid.w);
    up = fluid.y * fluid.w;
#endif
    // A non-finite wind (an overflowing eq. 4.1) would select an undefined pose: none.
    if (any(isnan(f)) || any(isinf(f)) || isnan(up) || isinf(up)) {
        f = vec2(0.0);
        up = 0.0;
    }
    corners[index] = vec4(f.x, up, f.y, exposure);
}
