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

// Cells per side of a level's window, and the levels: specialization constants (common.glsl
// says why; the frame's `ground` holds the same for the CPU's side). Read from the uniform block,
// lavapipe compiled a variant of the cull's tiles and count passes each frame (2.5 ms a frame
// each, `meadow timing`); from its storage twin, every point paid a load per SIMD lane.
uint ground_cells() {
    return GROUND_CELLS;
}

uint ground_levels() {
    return max(GROUND_LEVELS, 1u);
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

// How many cells local vertex (or point) `v` of a window of `n` cells lies inside its edge
// (Chebyshev).
float ground_edge_cells(vec2 v, uint n) {
    return min(min(v.x, v.y), min(float(n) - v.x, float(n) - v.y));
}

// The finest of `levels` levels of `cells` cells whose window holds `p` (relative to O; a
// window's edge belongs to it), and where `p` lies in it in cells (`g`). Past the coarsest
// window, the coarsest. Finest first, so a point near the camera (every root) stops at level 0.
uint ground_level_at(vec2 p, uvec2 shape, out vec2 g) {
    for (uint l = 0u; l + 1u < shape.y; l++) {
        g = (p - ground_level_offset(l)) / ground_level_step(l);
        if (ground_edge_cells(g, shape.x) >= 0.0) {
            return l;
        }
    }
    uint top = shape.y - 1u;
    g = (p - ground_level_offset(top)) / ground_level_step(top);
    return top;
}

// The clipmap's shape: (cells per side, levels).
uvec2 ground_shape() {
    return uvec2(ground_cells(), ground_levels());
}

// The clipmap's tiles (`render::ground::tiles`): GROUND_TILE_CELLS² cells of a level each, from
// its window's first vertex, row by row; their texels follow every level's vertices.
uint ground_tiles_per_side() {
    return (ground_cells() + GROUND_TILE_CELLS - 1u) / GROUND_TILE_CELLS;
}

// The texel of tile `tile` of level `level`.
int ground_tile_texel(uint level, uvec2 tile) {
    uint n = ground_cells() + 1u;
    uint t = ground_tiles_per_side();
    return int(ground_levels() * n * n + (level * t + tile.y) * t + tile.x);
}

#ifndef GROUND_WRITER
// A level as a point's reads need it, read once: its index, its window's cells and toroidal base,
// whether a coarser level follows (its odd vertices morph), its step and its texels' run.
struct GroundLevel {
    uint level;
    uint cells;
    bool next;
    uvec2 base;
    float step;
    float run;
};

GroundLevel ground_level(uint level, uvec2 shape) {
    GroundLevel l;
    l.level = level;
    l.cells = shape.x;
    l.next = level + 1u < shape.y;
    ivec4 window = frame_values.ground_windows[level];
    l.base = uvec2(window.xy);
    vec4 placed = frame_values.ground_levels[level];
    l.step = placed.z;
    l.run = placed.w;
    return l;
}

// The slot of local vertex v of level `l` (clamped to its window) in the camera grid (the
// window's toroidal base; a stored terrain's is 0, its texels row by row).
int ground_slot(GroundLevel l, ivec2 v) {
    int n = int(l.cells) + 1;
    v = clamp(v, ivec2(0), ivec2(n - 1));
    uvec3 dims = uvec3(n, 1, n);
    return int(l.level * uint(n * n) + camera_grid_slot(uvec3(v.x, 0, v.y), uvec3(l.base.x, 0u, l.base.y), dims));
}

vec4 ground_grid_texel(GroundLevel l, ivec2 v) {
    return ground_texel(ground_slot(l, v));
}

// The ground's cover at local vertex v of level `l`: the grass's (x) and the flowers' (y)
// densities (1 without cover rules: GROUND_COVER).
vec2 ground_vertex_covers(GroundLevel l, ivec2 v) {
    return GROUND_COVER != 0u ? ground_cover_texel(ground_slot(l, v)) : vec2(1.0);
}

// The grass's cover at local vertex v of level `l`.
float ground_vertex_cover(GroundLevel l, ivec2 v) {
    return ground_vertex_covers(l, v).x;
}

// The drawn ground's height at local vertex v of level `l` from its texel `t`. Below the
// coarsest level, within GROUND_MORPH_END cells of the window's edge an odd vertex's height
// slides onto the next level's mesh, and within GROUND_MORPH_FULL it is that mesh, so a level
// meets the next without cracks and the cull's roots, interpolating this grid, sit on the ground
// as drawn (`render::ground_clipmap::morph`, CDLOD's morph by the vertex's place in its window).
float ground_vertex_height(GroundLevel l, ivec2 v, vec4 t) {
    float next = l.next && ((v.x | v.y) & 1) != 0 ? 1.0 : 0.0;
    float band = float(GROUND_MORPH_END - GROUND_MORPH_FULL);
    float edge = ground_edge_cells(vec2(clamp(v, ivec2(0), ivec2(l.cells))), l.cells);
    float k = next * clamp((float(GROUND_MORPH_END) - edge) / band, 0.0, 1.0);
    return k > 0.0 ? mix(t.x, t.y, k) : t.x;
}

// Local vertex v of level `l`: the drawn ground's height there (x) and the ground's normal at the
// vertex (yzw, not normalized: its rise over the level's run).
vec4 ground_vertex(GroundLevel l, ivec2 v) {
    vec4 t = ground_grid_texel(l, v);
    return vec4(ground_vertex_height(l, v, t), -t.z, l.run, -t.w);
}

// The level and cell under `p` (relative to O), clamped to the level's window, and where `p`
// lies in the cell.
ivec2 ground_cell(vec2 p, out GroundLevel l, out vec2 f) {
    uvec2 shape = ground_shape();
    vec2 g;
    l = ground_level(ground_level_at(p, shape, g), shape);
    ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(int(shape.x) - 1));
    f = clamp(g - vec2(c), vec2(0.0), vec2(1.0));
    return c;
}

// The drawn heights at the four corners of cell `c` of level `l`: h00, h10, h01, h11.
vec4 ground_cell_heights(GroundLevel l, ivec2 c) {
    return vec4(ground_vertex(l, c).x, ground_vertex(l, c + ivec2(1, 0)).x, ground_vertex(l, c + ivec2(0, 1)).x,
        ground_vertex(l, c + ivec2(1, 1)).x);
}

// Height of the drawn ground at `p` (relative to O): the heights at the corners of its cell in
// the level that draws it, split as terrain.vert splits it, so a root sits on the ground as drawn.
float ground_height(vec2 p) {
    GroundLevel l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    return terrain_mesh_height(f, ground_cell_heights(l, c));
}

// The ground's covers at `p`, the grass's (x) and the flowers' (y): bilinear between its
// cell's vertices (`scene::cover`).
vec2 ground_covers(vec2 p) {
    if (GROUND_COVER == 0u) {
        return vec2(1.0);
    }
    GroundLevel l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    vec2 bottom = mix(ground_vertex_covers(l, c), ground_vertex_covers(l, c + ivec2(1, 0)), f.x);
    vec2 top = mix(ground_vertex_covers(l, c + ivec2(0, 1)), ground_vertex_covers(l, c + ivec2(1, 1)), f.x);
    return mix(bottom, top, f.y);
}

// The grass's cover at `p`.
float ground_cover(vec2 p) {
    return ground_covers(p).x;
}

// The cover debug view's colour (`--debug-view cover`): red where bare, yellow at half, green
// where full.
vec3 cover_debug_color(float cover) {
    return cover < 0.5 ? mix(vec3(0.8, 0.05, 0.02), vec3(0.8, 0.7, 0.05), 2.0 * cover)
                       : mix(vec3(0.8, 0.7, 0.05), vec3(0.05, 0.6, 0.1), 2.0 * cover - 1.0);
}

// Tile `tile` of level `l` as the source's tiles pass writes it (terrain/ground_tiles.comp): the
// lowest and highest height of its vertices' texels (their own and the next level's mesh there,
// between which a drawn vertex slides), the most grass and flower cover at them.
vec4 ground_tile_of(GroundLevel l, uvec2 tile) {
    ivec2 first = ivec2(tile * GROUND_TILE_CELLS);
    ivec2 last = min(first + int(GROUND_TILE_CELLS), ivec2(l.cells));
    vec4 bounds = vec4(1e30, -1e30, 0.0, 0.0);
    for (int z = first.y; z <= last.y; z++) {
        for (int x = first.x; x <= last.x; x++) {
            vec4 t = ground_grid_texel(l, ivec2(x, z));
            bounds.x = min(bounds.x, min(t.x, t.y));
            bounds.y = max(bounds.y, max(t.x, t.y));
            bounds.zw = max(bounds.zw, ground_vertex_covers(l, ivec2(x, z)));
        }
    }
    return bounds;
}

// The drawn ground over the square `lo`..`hi` (x, z, relative to O) from the clipmap's tiles: x the
// lowest height, y the highest, z the most grass cover and w the most flower cover, over the
// tiles under it in every level that draws a point of it (the levels of its corners: a window is
// larger than any square asked, so one of its corners lies in the finest). A drawn point lies in
// a cell whose corners are its tile's vertices, each drawn between its texel's own height and the
// next level's mesh there (the morph), both of which the tile bounds: the bounds hold for the
// ground as drawn. Past the coarsest window, its edge tiles (the drawn ground is held there).
vec4 ground_tile_bounds(vec2 lo, vec2 hi) {
    uvec2 shape = ground_shape();
    vec2 g;
    uint a = ground_level_at(lo, shape, g);
    uint b = ground_level_at(hi, shape, g);
    uint c = ground_level_at(vec2(lo.x, hi.y), shape, g);
    uint d = ground_level_at(vec2(hi.x, lo.y), shape, g);
    uint finest = min(min(a, b), min(c, d));
    uint coarsest = max(max(a, b), max(c, d));
    int last = int(shape.x) - 1;
    vec4 bounds = vec4(1e30, -1e30, 0.0, 0.0);
    for (uint level = finest; level <= coarsest; level++) {
        vec2 offset = ground_level_offset(level);
        float step = ground_level_step(level);
        // The cells from lo's to the last that starts before hi: a point on a cell's far edge is
        // the next cell's corner, in this tile too (a tile holds its edge vertices), so a block
        // cell on level 0's lattice reads the one tile it fills.
        ivec2 from = clamp(ivec2(floor((lo - offset) / step)), ivec2(0), ivec2(last));
        ivec2 to = clamp(max(ivec2(ceil((hi - offset) / step)) - 1, from), ivec2(0), ivec2(last));
        uvec2 first = uvec2(from) / GROUND_TILE_CELLS;
        uvec2 end = uvec2(to) / GROUND_TILE_CELLS;
        for (uint z = first.y; z <= end.y; z++) {
            for (uint x = first.x; x <= end.x; x++) {
                vec4 t = ground_texel(ground_tile_texel(level, uvec2(x, z)));
                bounds = vec4(min(bounds.x, t.x), max(bounds.y, t.y), max(bounds.zw, t.zw));
            }
        }
    }
    return bounds;
}

// The ground's normal at `p`: the bilinear patch's through the drawn heights of its cell
// (ground_patch.glsl), Belyaev §2.3's N_L under a blade's root.
vec3 ground_normal(vec2 p) {
    GroundLevel l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    return bilinear_patch_normal(f, ground_cell_heights(l, c), l.step);
}

// The ground's normal at the grid vertex nearest `p` in the level that holds it (the cull's
// normal under a tile, Belyaev's n of §2.2).
vec3 ground_vertex_normal(vec2 p) {
    uvec2 shape = ground_shape();
    vec2 g;
    GroundLevel l = ground_level(ground_level_at(p, shape, g), shape);
    return normalize(ground_vertex(l, ivec2(round(g))).yzw);
}
#endif

#endif
