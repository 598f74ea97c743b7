// `render::wind::params::Params`: the wind field's parameters of one frame, as the corner pass
// (`wind/analytic_corners.comp`) and the fluid's steps (`wind/fluid.comp`) declare them. One block
// bound twice: its values as a uniform block (one load for every lane on llvmpipe, where a
// storage load is a loop over the lanes), its counts and flags, which decide control flow,
// through a storage binding (the lavapipe profile's rule, common/profile.glsl).
#ifndef MEADOW_WIND_PARAMS_GLSL
#define MEADOW_WIND_PARAMS_GLSL
#include "common/shared.glsl"

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
    uvec4 perlin_mips[WIND_LEVELS]; /* per level, each layer's mip of the noise */ \
    uvec4 fluid_dims;    /* the fluid grid: cells per axis (x, y up, z), its inflow faces (bits x-, x+, z-, z+) */ \
    uvec4 fluid_base;    /* the window's toroidal base (x, y, z), the pressure iterations */ \
    uvec4 fluid_counts;  /* sources, colliders, 0, 0 */ \
    vec4 fluid_cell;     /* a cell's edges (x, y, z) in m, the step dt in s */ \
    vec4 fluid_corner;   /* the window's first corner relative to O (x, z), the blades' sample height (m), the blend band (cells) */ \
    vec4 fluid_coef;     /* the diffusion's ν dt / h² per axis (x, y, z), w unused */ \
    vec4 fluid_sources[MAX_FLUID_SOURCES];       /* x, z relative to O, height above the ground (m), the jet's speed (m/s) */ \
    vec4 fluid_colliders[2u * MAX_FLUID_COLLIDERS]; /* per collider: centre (x, height above the ground, z relative to O), radii */

#endif
