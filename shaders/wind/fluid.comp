#version 460
#extension GL_GOOGLE_include_directive : require
// One step of the fluid wind (`render::wind::fluid`; Zhang Xia §2 after Stam 1999, eq. 2:
// ∂u/∂t = −(u·∇)u + ν∇²u + f, with ∇·u = 0), one variant per stage, each a dispatch over the
// window's cells (`render::wind::fluid::pass`): the upwind ghosts' analytic wind (`inflow`), the
// cells that entered the window start from the analytic field (`enter`), the sources, calm areas
// and colliders (`forces`, f), the implicit diffusion of eq. 4 by Jacobi iterations (`diffuse`,
// in place of Zhang Xia's Gauss–Seidel, which a GPU cannot run in place), the semi-Lagrangian
// self-advection of §2.3.3 (`advect`), the divergence (`divergence`), the pressure's Poisson
// equation by Jacobi iterations with the Chebyshev semi-iteration's weights (`pressure`) and the
// subtraction of its gradient (`project`, §2.3.6). The divergence and the gradient are central
// differences, and the pressure solves ∇·∇p = ∇·u for that very pair (the row of D·G, ghosts
// included), so a converged solve leaves no divergence by the solver's own operator. The CPU mirror is `render::wind::fluid::scheme`, line for line.
// variant enter: STEP_ENTER
// variant forces: STEP_FORCES
// variant diffuse: STEP_DIFFUSE
// variant advect: STEP_ADVECT
// variant divergence: STEP_DIVERGENCE
// variant pressure: STEP_PRESSURE
// variant project: STEP_PROJECT
// variant inflow: STEP_INFLOW
#include "common/shared.glsl"
#include "common/camera_grid.glsl"
#include "wind/params.glsl"

layout(local_size_x = FLUID_GROUP) in;

layout(set = 0, binding = 0, std140) uniform WindValues { WIND_PARAMS } wind;
layout(set = 0, binding = 1, std430) readonly buffer WindControl { WIND_PARAMS } control;
// Velocities read (xyz, m/s), the right-hand side of the diffusion, velocities written.
layout(set = 0, binding = 2, rgba32f) uniform readonly image3D Src;
layout(set = 0, binding = 3, rgba32f) uniform readonly image3D Rhs;
layout(set = 0, binding = 4, rgba32f) uniform writeonly image3D Dst;
// Pressure read and written; the divergence and its row's diagonal (the Jacobi's divisor).
layout(set = 0, binding = 5, r32f) uniform readonly image3D PIn;
layout(set = 0, binding = 6, r32f) uniform writeonly image3D POut;
layout(set = 0, binding = 7, rg32f) uniform image3D DivDiag;
// The analytic wind of the ghost columns around the window (`fluid_ring_texel`), written by the
// inflow stage at the step's start.
layout(set = 0, binding = 8, rgba32f) uniform image3D Inflow;
#ifdef STEP_PRESSURE
// The iteration's weight ω_k (x, `render::wind::fluid::pressure_weight`), over the first bytes
// of the range the enter stage's fill takes (no other stage reads push constants).
layout(push_constant) uniform Push { vec4 pressure; } push;
#else
layout(push_constant) uniform Push { CameraGridFill fill; } push;
#endif

#include "wind/fluid.glsl"

const float FLUID_SOURCE_RADIUS = 1.0; // render::wind::fluid::SOURCE_RADIUS
const float FLUID_SOURCE_TIME = 0.25;  // render::wind::fluid::SOURCE_TIME
const float FLUID_CALM_DAMPING = 4.0;  // render::wind::fluid::CALM_DAMPING

// A ghost's pressure: 0 past a downwind face (the outflow's reference), the cell inside past an
// upwind face, the ground and the top (no flow through them: zero gradient). `delta`: the
// coefficient of cell `centre` instead (a row's diagonal).
float pressure_at(ivec3 c, ivec3 centre, bool delta) {
    ivec3 d = fluid_n;
    bool outside = c.x < 0 || c.z < 0 || c.x >= d.x || c.z >= d.z;
    if (outside && !fluid_upwind(c)) {
        return 0.0;
    }
    ivec3 r = clamp(c, ivec3(0), d - 1);
    if (delta) {
        return all(equal(r, centre)) ? 1.0 : 0.0;
    }
    return imageLoad(PIn, fluid_texel(r)).x;
}

// Component `k` of G p at local cell `c` inside the window: a central difference.
float gradient_inside(ivec3 c, int k, ivec3 centre, bool delta) {
    ivec3 e = ivec3(0);
    e[k] = 1;
    return (pressure_at(c + e, centre, delta) - pressure_at(c - e, centre, delta)) / (2.0 * wind.fluid_cell[k]);
}

// Component `k` of G p at any local cell, a ghost's by the velocity's rule: nothing past an
// upwind face (its velocity is the analytic wind, which the projection does not change), the
// cell inside's otherwise, mirrored at the ground and the top.
float gradient_at(ivec3 c, int k, ivec3 centre, bool delta) {
    if (fluid_upwind(c)) {
        return 0.0;
    }
    bool mirrored;
    float g = gradient_inside(fluid_inside(c, mirrored), k, centre, delta);
    return mirrored && k == 1 ? -g : g;
}

// (D G p) at local cell `c`: the solver's Laplacian row. Two cells or more from every face it is
// the wide stencil Σ_k (p[c + 2e_k] − 2 p[c] + p[c − 2e_k]) / (4 h_k²), the same sum with no ghost.
float laplacian(ivec3 c, bool delta) {
    vec3 h = wind.fluid_cell.xyz;
    if (!delta && all(greaterThanEqual(c, ivec3(2))) && all(lessThan(c, fluid_n - 2))) {
        float p = imageLoad(PIn, fluid_texel(c)).x;
        float sum = 0.0;
        for (int k = 0; k < 3; k++) {
            ivec3 e = ivec3(0);
            e[k] = 2;
            float side = imageLoad(PIn, fluid_texel(c + e)).x + imageLoad(PIn, fluid_texel(c - e)).x;
            sum += (side - 2.0 * p) / (4.0 * h[k] * h[k]);
        }
        return sum;
    }
    float sum = 0.0;
    for (int k = 0; k < 3; k++) {
        ivec3 e = ivec3(0);
        e[k] = 1;
        sum += (gradient_at(c + e, k, c, delta) - gradient_at(c - e, k, c, delta)) / (2.0 * h[k]);
    }
    return sum;
}

// D u at local cell `c`: central differences of the velocities read, ghosts included.
float divergence(ivec3 c) {
    vec3 h = wind.fluid_cell.xyz;
    ivec3 x = ivec3(1, 0, 0), y = ivec3(0, 1, 0), z = ivec3(0, 0, 1);
    return (fluid_velocity(c + x).x - fluid_velocity(c - x).x) / (2.0 * h.x)
        + (fluid_velocity(c + y).y - fluid_velocity(c - y).y) / (2.0 * h.y)
        + (fluid_velocity(c + z).z - fluid_velocity(c - z).z) / (2.0 * h.z);
}

// Whether local cell `c` lies inside a collider: a solid cell, its velocity 0.
bool solid(ivec3 c) {
    vec3 p = fluid_centre(c);
    uint colliders = control.fluid_counts.y;
    for (uint i = 0u; i < colliders; i++) {
        vec3 q = (p - wind.fluid_colliders[2u * i].xyz) / wind.fluid_colliders[2u * i + 1u].xyz;
        if (dot(q, q) <= 1.0) {
            return true;
        }
    }
    return false;
}

// f: each source relaxes the velocity towards its downward jet over FLUID_SOURCE_TIME, weighted by
// a Gaussian of FLUID_SOURCE_RADIUS about its point; calm areas damp it; colliders are solid.
vec3 forced(ivec3 c, vec3 u) {
    vec3 p = fluid_centre(c);
    float dt = wind.fluid_cell.w;
    uint sources = control.fluid_counts.x;
    for (uint i = 0u; i < sources; i++) {
        vec4 s = wind.fluid_sources[i];
        vec3 r = p - vec3(s.x, s.z, s.y);
        float g = exp(-dot(r, r) / (2.0 * FLUID_SOURCE_RADIUS * FLUID_SOURCE_RADIUS));
        u += min(1.0, dt / FLUID_SOURCE_TIME) * g * (vec3(0.0, -s.w, 0.0) - u);
    }
    uint calm = control.counts.z;
    for (uint i = 0u; i < calm; i++) {
        vec4 a = wind.calm[i];
        if (all(greaterThanEqual(p.xz, a.xy)) && all(lessThanEqual(p.xz, a.zw))) {
            u *= exp(-dt * FLUID_CALM_DAMPING);
        }
    }
    return solid(c) ? vec3(0.0) : u;
}

void main() {
    fluid_load_control();
    ivec3 d = fluid_n;
#if defined(STEP_INFLOW)
    // Each texel of the ring (`fluid_ring_texel`, its inverse): the analytic wind at its column.
    ivec3 size = imageSize(Inflow);
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(size.x * size.y)) {
        return;
    }
    int col = int(index % uint(size.x)), row = int(index / uint(size.x));
    ivec2 xz = row == 0 ? ivec2(col - 1, -1) : (row == 1 ? ivec2(col - 1, d.z) : (row == 2 ? ivec2(-1, col) : ivec2(d.x, col)));
    imageStore(Inflow, ivec3(col, row, 0), vec4(fluid_analytic(ivec3(xz.x, 0, xz.y)), 0.0));
#elif defined(STEP_ENTER)
    ivec3 c = ivec3(camera_grid_entered(push.fill, gl_GlobalInvocationID.x));
    imageStore(Dst, fluid_texel(c), vec4(fluid_analytic(c), 0.0));
    imageStore(POut, fluid_texel(c), vec4(0.0));
#else
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(d.x * d.y * d.z)) {
        return;
    }
    ivec3 c = ivec3(index % uint(d.x), (index / uint(d.x)) % uint(d.y), index / uint(d.x * d.y));
    ivec3 t = fluid_texel(c);
#if defined(STEP_FORCES)
    imageStore(Dst, t, vec4(forced(c, imageLoad(Src, t).xyz), 0.0));
#elif defined(STEP_DIFFUSE)
    // Eq. 4 by one Jacobi iteration: x = (x0 + Σ a_k (x[c + e_k] + x[c − e_k])) / (1 + 2 Σ a_k).
    vec3 a = wind.fluid_coef.xyz;
    ivec3 x = ivec3(1, 0, 0), y = ivec3(0, 1, 0), z = ivec3(0, 0, 1);
    vec3 sum = a.x * (fluid_velocity(c + x) + fluid_velocity(c - x)) + a.y * (fluid_velocity(c + y) + fluid_velocity(c - y))
        + a.z * (fluid_velocity(c + z) + fluid_velocity(c - z));
    vec3 v = (imageLoad(Rhs, t).xyz + sum) / (1.0 + 2.0 * (a.x + a.y + a.z));
    imageStore(Dst, t, vec4(v, 0.0));
#elif defined(STEP_ADVECT)
    // §2.3.3: back along the velocity by one step, tri-linearly, the ghosts' values past the faces.
    vec3 back = vec3(c) - wind.fluid_cell.w * imageLoad(Src, t).xyz / wind.fluid_cell.xyz;
    back = clamp(back, vec3(-1.0), vec3(d));
    imageStore(Dst, t, vec4(fluid_sample(back), 0.0));
#elif defined(STEP_DIVERGENCE)
    imageStore(DivDiag, t, vec4(divergence(c), laplacian(c, true), 0.0, 0.0));
#elif defined(STEP_PRESSURE)
    // Jacobi with the Chebyshev semi-iteration's weights on (D G) p = D u:
    // p += ω_k (D u − (D G p)) / diag.
    vec2 dd = imageLoad(DivDiag, t).xy;
    float p = imageLoad(PIn, t).x;
    imageStore(POut, t, vec4(p + push.pressure.x * (dd.x - laplacian(c, false)) / dd.y));
#elif defined(STEP_PROJECT)
    vec3 g = vec3(gradient_inside(c, 0, c, false), gradient_inside(c, 1, c, false), gradient_inside(c, 2, c, false));
    vec3 u = imageLoad(Src, t).xyz - g;
    imageStore(Dst, t, vec4(solid(c) ? vec3(0.0) : u, 0.0));
#endif
#endif
}
