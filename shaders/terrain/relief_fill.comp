#version 460
#extension GL_GOOGLE_include_directive : require
// The relief's fill of a block field's ground clipmap (`render::ground::relief::ReliefGround`,
// `render::ground_clipmap`): one level of a camera grid (`render::camera_grid`, (cells + 1)²
// vertices on the world's lattice of the level's step), the vertices that entered its window since
// the last fill (`render::passes::ground_fill`), each with what depends on its world vertex alone:
// the relief's height, the next level's mesh's height there and the relief's slope (its rise over
// 1 m, the level's `ground_level_rise_run`: a central difference). Readers apply the morph by the vertex's place in its
// window (common/ground.glsl: `ground_vertex`).
//
// World-exact: a vertex is named by its place in half-metres on the world's period, X and Z, and
// wave k's phase is 2π ((m_k X + n_k Z) mod P) / P + φ_k in whole numbers (m_k, n_k its periods
// in the world's, taken mod P on the CPU so the products fit 32 bits unsigned), not relative to
// O: the texels a scroll keeps are the ones a fresh fill writes, and a level's even vertex is bit
// for bit the next level's vertex at the same place.
#define GROUND_WRITER
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/camera_grid.glsl"
#include "terrain/cover_fill.glsl"

layout(local_size_x = CAMERA_GRID_GROUP) in;

layout(push_constant) uniform Fill {
    CameraGridFill fill;
};

// The relief at the world vertex `at` (half-metres on the world's period).
float relief_at(uvec2 at) {
    float h = 0.0;
    for (uint k = 0u; k < RELIEF_WAVES; k++) {
        ivec4 c = frame_values.relief_cycles[k / 2u];
        uvec2 mn = uvec2((k & 1u) == 0u ? c.xy : c.zw);
        uint q = (mn.x * at.x + mn.y * at.y) % PERIOD_HALF_METRES;
        vec4 w = frame_values.relief_waves[k];
        float theta = float(q) * (2.0 * PI / float(PERIOD_HALF_METRES)) + w.w;
        h += w.z * sin(theta);
    }
    return h;
}

void main() {
    uvec3 local = camera_grid_entered(fill, gl_GlobalInvocationID.x);
    uint level = fill.base.w;
    ivec4 window = frame_values.ground_windows[level];
    uint step = uint(2.0 * ground_level_step(level)); // half-metres
    uvec2 at = (uvec2(window.zw) + local.xz * step) % PERIOD_HALF_METRES;
    float h = relief_at(at);
    // The slope: the relief's central difference over half a metre either side, the ground's one
    // definition of a vertex's slope (the stored terrain's over its 0.5 m lattice, a heightmap's
    // over a texel, heightmap_fill.comp), so a relief and its 16-bit export (0.5 m texels) light
    // alike. Its analytic gradient lit them 1° apart on the 6 m waves (sin(kh)/kh = 0.955).
    uvec2 dx = uvec2(1u, 0u);
    uvec2 dz = uvec2(0u, 1u);
    uvec2 wrap = uvec2(PERIOD_HALF_METRES);
    vec2 slope = vec2(relief_at((at + dx) % PERIOD_HALF_METRES) - relief_at((at + wrap - dx) % PERIOD_HALF_METRES),
        relief_at((at + dz) % PERIOD_HALF_METRES) - relief_at((at + wrap - dz) % PERIOD_HALF_METRES));
    // The next level's mesh at an odd vertex: the mean of the two even vertices of the coarse
    // edge along x or z, or of the coarse cell's diagonal, that it halves (split (0,0)-(1,1) like
    // the fine cells). The window's first vertex is even (a multiple of GROUND_SNAP_CELLS), so a
    // vertex's parity in the window is its parity in the world.
    float coarse = h;
    uvec2 odd = local.xz & 1u;
    if ((odd.x | odd.y) != 0u) {
        uvec2 across = odd * step;
        uvec2 before = (at + uvec2(PERIOD_HALF_METRES) - across) % PERIOD_HALF_METRES;
        uvec2 after = (at + across) % PERIOD_HALF_METRES;
        coarse = 0.5 * (relief_at(before) + relief_at(after));
    }
    uvec3 dims = fill.dims.xyz;
    uint slot = level * dims.x * dims.z + camera_grid_slot(local, fill.base.xyz, dims);
    ground_grid[slot] = vec4(h, coarse, slope);
    ground_cover_grid[slot] = GROUND_COVER != 0u ? ground_cover_at(world_metres(at), slope) : packUnorm2x16(vec2(1.0));
}
