// The fluid wind's grid (`render::wind::fluid`, Zhang Xia §2 after Stam): cell-centred velocities
// in a 3-D window of `fluid_dims` cells that follows the camera by whole cells in x and z
// (toroidal: world cell w in slot w mod dims, `render::camera_grid`) and stands on the ground in
// y: layer j is (j + ½)·dy above the local ground, so a hill does not sit inside the box. The
// boundary is given by ghost cells (`fluid_velocity`): an upwind face (the global wind crosses it
// inwards) takes the analytic wind, a downwind face the edge cell's (zero gradient), and the
// ground and the top mirror the cell inside with its vertical component negated (no
// penetration, free slip). Mirrored on the CPU by `render::wind::fluid::scheme`. The includer
// declares `wind` and `control` (`wind/params.glsl`), `Src`, the velocities read, and `Inflow`,
// the upwind ghosts' analytic wind (`fluid_ring_texel`).
#ifndef MEADOW_WIND_FLUID_GLSL
#define MEADOW_WIND_FLUID_GLSL
#include "wind/analytic.glsl"

// The grid's shape and faces, read once per invocation from the storage binding (`control`, the
// lavapipe profile's rule for values that decide control flow; on llvmpipe each storage load is
// a loop over the lanes): `fluid_load_control` at the top of `main`.
ivec3 fluid_n;
uint fluid_faces;
float fluid_global;

void fluid_load_control() {
    fluid_n = ivec3(control.fluid_dims.xyz);
    fluid_faces = control.fluid_dims.w;
    fluid_global = control.global.w;
}

// The image texel of local cell `c` (each axis inside the window): the toroidal wrap.
ivec3 fluid_texel(ivec3 c) {
    ivec3 d = ivec3(wind.fluid_dims.xyz);
    ivec3 s = c + ivec3(wind.fluid_base.xyz);
    return s - d * ivec3(greaterThanEqual(s, d));
}

// The centre of local cell `c` relative to O (x, z) and its height above the ground (y).
vec3 fluid_centre(ivec3 c) {
    vec3 h = wind.fluid_cell.xyz;
    vec3 p = (vec3(c) + 0.5) * h;
    return vec3(wind.fluid_corner.x + p.x, p.y, wind.fluid_corner.y + p.z);
}

// The analytic wind at local cell `c` (its global wind with gusts; the sources are injected): an
// upwind ghost's inflow, and what a cell that enters the window starts from.
vec3 fluid_analytic(ivec3 c) {
    if (fluid_global < 0.5) {
        return vec3(0.0);
    }
    vec2 v = global_wind(wind.global.xy, wind.global.z, fluid_global > 1.5, wind.phases, wind.waves01, wind.waves23,
        fluid_centre(c).xz);
    return vec3(v.x, 0.0, v.y);
}

// Whether local cell `c` lies past an upwind face (bits x-, x+, z-, z+ of `fluid_dims.w`).
bool fluid_upwind(ivec3 c) {
    ivec3 d = fluid_n;
    uint faces = fluid_faces;
    return (c.x < 0 && (faces & 1u) != 0u) || (c.x >= d.x && (faces & 2u) != 0u) || (c.z < 0 && (faces & 4u) != 0u)
        || (c.z >= d.z && (faces & 8u) != 0u);
}

// The cell inside the window whose value a ghost `c` takes (x and z clamped: zero gradient; y
// mirrored about the ground and the top), and whether its vertical component is negated.
ivec3 fluid_inside(ivec3 c, out bool mirrored) {
    ivec3 d = fluid_n;
    mirrored = c.y < 0 || c.y >= d.y;
    int y = c.y < 0 ? -1 - c.y : (c.y >= d.y ? 2 * d.y - 1 - c.y : c.y);
    return clamp(ivec3(c.x, y, c.z), ivec3(0), d - 1);
}

// The ring of ghost columns around the window (x in [-1, nx], z in [-1, nz], outside it): the
// texel of `Inflow` that holds column `xz`'s analytic wind. Rows 0 and 1 are the faces z = -1
// and z = nz by x + 1, rows 2 and 3 the faces x = -1 and x = nx by z (`fluid.comp`'s inflow stage
// writes them). A column past the ring (a zero weight of `fluid_sample` at the grid's far edge)
// reads its nearest.
ivec3 fluid_ring_texel(ivec2 xz) {
    ivec2 d = fluid_n.xz;
    xz = clamp(xz, ivec2(-1), d);
    int row = xz.y < 0 ? 0 : (xz.y >= d.y ? 1 : (xz.x < 0 ? 2 : 3));
    return ivec3(row < 2 ? xz.x + 1 : xz.y, row, 0);
}

// The velocity of local cell `c` (m/s), ghosts included. An upwind ghost's analytic wind is read
// from `Inflow`, written once a step: llvmpipe runs an `if`'s body under a lane mask whether a
// lane takes it or not, so evaluating it here cost every call its four `sin`.
vec3 fluid_velocity(ivec3 c) {
    if (fluid_upwind(c)) {
        return imageLoad(Inflow, fluid_ring_texel(c.xz)).xyz;
    }
    bool mirrored;
    vec3 v = imageLoad(Src, fluid_texel(fluid_inside(c, mirrored))).xyz;
    return mirrored ? vec3(v.x, -v.y, v.z) : v;
}

// Zhang Xia's tri-linear interpolation (§3.2.2) at `g`, in cells (cell centres at whole
// numbers), ghosts included.
vec3 fluid_sample(vec3 g) {
    vec3 i = floor(g);
    vec3 f = g - i;
    ivec3 c = ivec3(i);
    vec3 x00 = mix(fluid_velocity(c), fluid_velocity(c + ivec3(1, 0, 0)), f.x);
    vec3 x10 = mix(fluid_velocity(c + ivec3(0, 1, 0)), fluid_velocity(c + ivec3(1, 1, 0)), f.x);
    vec3 x01 = mix(fluid_velocity(c + ivec3(0, 0, 1)), fluid_velocity(c + ivec3(1, 0, 1)), f.x);
    vec3 x11 = mix(fluid_velocity(c + ivec3(0, 1, 1)), fluid_velocity(c + ivec3(1, 1, 1)), f.x);
    return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
}

#endif
