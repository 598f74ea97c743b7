// The ground under the grass, whatever its source (`render::ground`: a stored terrain's grid or a
// block field's relief): the levels of one clipmap (`ground_texels.glsl`), each a window of
// `ground_cells()`² cells at its own step, finest first. Every reader of the ground (the terrain
// mesh, the cull's roots and tile normals, the blades' lighting, the debug views) goes through
// this file; nothing here asks which source wrote the texels. Mirrors `render::ground` and
// `render::ground_clipmap` on the CPU.
#ifndef MEADOW_GROUND_GLSL
#define MEADOW_GROUND_GLSL
#include "common/camera_grid.glsl"
#include "common/ground_patch.glsl"

// Cells per side of a level's window, and the levels.
uint ground_cells() {
    return frame_values.ground.x;
}

uint ground_levels() {
    return max(frame_values.ground.z, 1u);
}

// Level l's window: its first vertex relative to O (the world's origin for a stored terrain),
// its cell edge (m), and the run its texels' rise is given over (m).
vec2 ground_level_offset(uint level) {
    return frame_values.ground_levels[level].xy;
}

float ground_level_step(uint level) {
    return frame_values.ground_levels[level].z;
}

float ground_level_rise_run(uint level) {
    return frame_values.ground_levels[level].w;
}

// How many cells local vertex (or point) `v` of a level's window lies inside its edge (Chebyshev).
float ground_edge_cells(vec2 v) {
    float n = float(ground_cells());
    return min(min(v.x, v.y), min(n - v.x, n - v.y));
}

// The finest level whose window holds `p` (relative to O; a window's edge belongs to it), and
// where `p` lies in it in cells (`g`). Past the coarsest window, the coarsest.
uint ground_level_at(vec2 p, out vec2 g) {
    uint levels = ground_levels();
    for (uint l = 0u; l + 1u < levels; l++) {
        g = (p - ground_level_offset(l)) / ground_level_step(l);
        if (ground_edge_cells(g) >= 0.0) {
            return l;
        }
    }
    uint top = levels - 1u;
    g = (p - ground_level_offset(top)) / ground_level_step(top);
    return top;
}

#ifndef GROUND_WRITER
// The texel of local vertex v of level `level` (clamped to its window), from its slot in the
// camera grid (the window's toroidal base in `ground_windows`; a stored terrain's is 0, its
// texels row by row).
vec4 ground_grid_texel(uint level, ivec2 v) {
    int n = int(ground_cells()) + 1;
    v = clamp(v, ivec2(0), ivec2(n - 1));
    uvec3 dims = uvec3(n, 1, n);
    ivec4 window = frame_values.ground_windows[level];
    uvec3 base = uvec3(window.x, 0, window.y);
    uint slot = level * uint(n * n) + camera_grid_slot(uvec3(v.x, 0, v.y), base, dims);
    return ground_texel(int(slot));
}

// The drawn ground's height at local vertex v of level `level`. Below the coarsest level, within
// GROUND_MORPH_END cells of the window's edge an odd vertex's height slides onto the next level's
// mesh, and within GROUND_MORPH_FULL it is that mesh, so a level meets the next without cracks
// and the cull's roots, interpolating this grid, sit on the ground as drawn
// (`render::ground_clipmap::morph`, CDLOD's morph by the vertex's place in its window).
float ground_vertex_height(uint level, ivec2 v, vec4 t) {
    float h = t.x;
    if (level + 1u < ground_levels() && ((v.x | v.y) & 1) != 0) {
        float band = float(GROUND_MORPH_END - GROUND_MORPH_FULL);
        float k = clamp((float(GROUND_MORPH_END) - ground_edge_cells(vec2(clamp(v, ivec2(0), ivec2(ground_cells()))))) / band, 0.0, 1.0);
        if (k > 0.0) {
            h = mix(h, t.y, k);
        }
    }
    return h;
}

// Local vertex v of level `level`: the drawn ground's height there (x) and the ground's normal
// at the vertex (yzw, not normalized: its rise over the level's run).
vec4 ground_vertex(uint level, ivec2 v) {
    vec4 t = ground_grid_texel(level, v);
    return vec4(ground_vertex_height(level, v, t), -t.z, ground_level_rise_run(level), -t.w);
}

// The level and cell under `p` (relative to O), clamped to the level's window, and where `p`
// lies in the cell.
ivec2 ground_cell(vec2 p, out uint level, out vec2 f) {
    vec2 g;
    level = ground_level_at(p, g);
    ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(int(ground_cells()) - 1));
    f = clamp(g - vec2(c), vec2(0.0), vec2(1.0));
    return c;
}

// The drawn heights at the four corners of the cell under `p`: h00, h10, h01, h11.
vec4 ground_cell_heights(uint level, ivec2 c) {
    return vec4(ground_vertex(level, c).x, ground_vertex(level, c + ivec2(1, 0)).x,
        ground_vertex(level, c + ivec2(0, 1)).x, ground_vertex(level, c + ivec2(1, 1)).x);
}

// Height of the drawn ground at `p` (relative to O): the heights at the corners of its cell in
// the level that draws it, split as terrain.vert splits it, so a root sits on the ground as drawn.
float ground_height(vec2 p) {
    uint l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    return terrain_mesh_height(f, ground_cell_heights(l, c));
}

// The ground's normal at `p`: the bilinear patch's through the drawn heights of its cell
// (ground_patch.glsl), Belyaev §2.3's N_L under a blade's root.
vec3 ground_normal(vec2 p) {
    uint l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    return bilinear_patch_normal(f, ground_cell_heights(l, c), ground_level_step(l));
}

// The ground's normal at the grid vertex nearest `p` in the level that holds it (the cull's
// normal under a tile, Belyaev's n of §2.2).
vec3 ground_vertex_normal(vec2 p) {
    vec2 g;
    uint l = ground_level_at(p, g);
    return normalize(ground_vertex(l, ivec2(round(g))).yzw);
}
#endif

#endif
