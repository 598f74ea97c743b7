// Block fields (`scene::field`, Belyaev §2.1): the relief and the blades of the cells around the
// origin O, every position relative to O (FrameUniforms' field part), so the numbers stay small
// wherever the camera is. Mirrors `scene::field` on the CPU.
#ifndef MEADOW_FIELD_GLSL
#define MEADOW_FIELD_GLSL
#include "common/camera_grid.glsl"
#include "common/rings.glsl"

const float TALLEST_BLADE = 0.55; // scene::blades::TALLEST
const float WIDEST_BLADE = 0.016; // scene::blades::WIDEST

// Roots are sunk this far below the drawn terrain (as a stored field's, `scene::blades::ROOT_SINK`).
const float FIELD_ROOT_SINK = 0.01;

// h(O + p) = Σ a_k sin(θ_k + u_k · p), θ_k = u_k · O + φ_k given as sin and cos.
float relief_height(vec2 p) {
    float h = 0.0;
    for (uint k = 0u; k < RELIEF_WAVES; k++) {
        vec4 w = frame_values.relief_waves[k];
        vec4 phase = frame_values.relief_phases[k / 2u];
        vec2 sc = (k & 1u) == 0u ? phase.xy : phase.zw;
        float a = dot(w.xy, p);
        h += w.z * (sc.x * cos(a) + sc.y * sin(a));
    }
    return h;
}

vec3 relief_normal(vec2 p) {
    vec2 slope = vec2(0.0);
    for (uint k = 0u; k < RELIEF_WAVES; k++) {
        vec4 w = frame_values.relief_waves[k];
        vec4 phase = frame_values.relief_phases[k / 2u];
        vec2 sc = (k & 1u) == 0u ? phase.xy : phase.zw;
        float a = dot(w.xy, p);
        slope += w.z * w.xy * (sc.y * cos(a) - sc.x * sin(a));
    }
    return normalize(vec3(-slope.x, 1.0, -slope.y));
}

// Whether integer cell `cell` belongs to the field (a bounded field is centred on the world's
// origin: cells -n/2 .. n/2 - 1).
bool field_has_cell(ivec2 cell) {
    int n = frame.field_cells.z;
    if (n == 0) {
        return true;
    }
    ivec2 lo = ivec2(-(n / 2));
    return all(greaterThanEqual(cell, lo)) && all(lessThan(cell, lo + ivec2(n)));
}

// The blocks' variation repeats every PERIOD_CELLS cells (`scene::field::WORLD_PERIOD`).
uint cell_hash(ivec2 cell) {
    ivec2 c = ((cell % PERIOD_CELLS) + PERIOD_CELLS) % PERIOD_CELLS;
    uint h = uint(c.x) * 0x8da6b343u ^ uint(c.y) * 0xd8163841u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    return h ^ (h >> 12);
}

// The ground's clipmap (`render::ground_clipmap`): its levels, and level l's window (its first
// vertex relative to O, its cell edge).
uint ground_levels() {
    return max(frame_values.relief_grid.z, 1u);
}

vec2 ground_level_offset(uint level) {
    return frame_values.ground_levels[level].xy;
}

float ground_level_step(uint level) {
    return frame_values.ground_levels[level].z;
}

// The world's period in half-metres, the lattice the clipmap's texels are evaluated on
// (`render::ground_clipmap::PERIOD_HALF_METRES`: a block is 8 half-metres).
const uint PERIOD_HALF_METRES = uint(PERIOD_CELLS) * 8u;

// Height of the drawn terrain (the relief at the grid's vertices, flat between them, split as
// terrain.vert splits a cell) from the heights of the cell's four vertices.
float terrain_mesh_height(vec2 f, float h00, float h10, float h01, float h11) {
    return f.x >= f.y ? h00 + f.x * (h10 - h00) + f.y * (h11 - h10) : h00 + f.y * (h01 - h00) + f.x * (h11 - h01);
}

// How many cells local vertex (or point) `v` of a level's window lies inside its edge (Chebyshev).
float ground_edge_cells(vec2 v) {
    float n = float(FIELD_TERRAIN_CELLS);
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

#ifndef RELIEF_GRID_WRITER
// Local vertex v of level `level` (clamped to its window): the drawn ground's height there and
// the relief's normal. The texel sits in the vertex's slot of the camera grid (the window's base
// in `ground_windows`); within GROUND_MORPH_END cells of the window's edge an odd vertex's height
// slides onto the next level's mesh, and within GROUND_MORPH_FULL it is that mesh, so a level
// meets the next without cracks and the cull's roots, interpolating this grid, sit on the ground
// as drawn (`render::ground_clipmap::morph`, CDLOD's morph by the vertex's place in its window).
vec4 ground_vertex(uint level, ivec2 v) {
    int n = int(FIELD_TERRAIN_CELLS) + 1;
    v = clamp(v, ivec2(0), ivec2(n - 1));
    uvec3 dims = uvec3(n, 1, n);
    ivec4 window = frame_values.ground_windows[level];
    uvec3 base = uvec3(window.x, 0, window.y);
    uint slot = level * uint(n * n) + camera_grid_slot(uvec3(v.x, 0, v.y), base, dims);
    vec4 t = relief_texel(int(slot));
    float h = t.x;
    if (((v.x | v.y) & 1) != 0) {
        float band = float(GROUND_MORPH_END - GROUND_MORPH_FULL);
        float k = clamp((float(GROUND_MORPH_END) - ground_edge_cells(vec2(v))) / band, 0.0, 1.0);
        if (k > 0.0) {
            h = mix(h, t.y, k);
        }
    }
    return vec4(h, t.z, sqrt(max(1.0 - t.z * t.z - t.w * t.w, 0.0)), t.w);
}

// The level and cell under `p` (relative to O), clamped to the level's window, and where `p`
// lies in the cell.
ivec2 ground_cell(vec2 p, out uint level, out vec2 f) {
    vec2 g;
    level = ground_level_at(p, g);
    ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(int(FIELD_TERRAIN_CELLS) - 1));
    f = clamp(g - vec2(c), vec2(0.0), vec2(1.0));
    return c;
}

// Height of the drawn ground at `p` (relative to O): the heights at the corners of its cell in
// the level that draws it, split as terrain.vert splits it, so a root sits on the ground as drawn.
float field_ground_height(vec2 p) {
    uint l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    float h00 = ground_vertex(l, c).x;
    float h10 = ground_vertex(l, c + ivec2(1, 0)).x;
    float h01 = ground_vertex(l, c + ivec2(0, 1)).x;
    return terrain_mesh_height(f, h00, h10, h01, ground_vertex(l, c + ivec2(1, 1)).x);
}

// The relief's normal at `p`: the vertices' normals of its cell, interpolated bilinearly.
vec3 field_ground_normal(vec2 p) {
    uint l;
    vec2 f;
    ivec2 c = ground_cell(p, l, f);
    vec3 bottom = mix(ground_vertex(l, c).yzw, ground_vertex(l, c + ivec2(1, 0)).yzw, f.x);
    vec3 top = mix(ground_vertex(l, c + ivec2(0, 1)).yzw, ground_vertex(l, c + ivec2(1, 1)).yzw, f.x);
    return normalize(mix(bottom, top, f.y));
}
#endif

// Blade `index` of the stored block as placed in `cell`: turned by a quarter turn k and mirrored
// per the cell's hash (a variation of the block, Belyaev §2.1), positioned relative to O; its
// height (y) is left to the caller (the cull sets it on the drawn terrain).
BladeInstance field_blade(ivec2 cell, uint index) {
    BladeInstance blade = blade_record(index);
    float edge = frame_values.field.x;
    uint h = cell_hash(cell);
    vec2 p = blade.position.xz - vec2(0.5 * edge);
    float facing = blade.facing;
    if ((h & 4u) != 0u) {
        // Mirror x: the normal (sin f, cos f) becomes (-sin f, cos f).
        p.x = -p.x;
        facing = -facing;
    }
    uint quarter = h & 3u;
    for (uint q = 0u; q < quarter; q++) {
        // A quarter turn about +y: (x, z) -> (z, -x), the facing angle grows by π/2.
        p = vec2(p.y, -p.x);
        facing += 0.5 * PI;
    }
    vec2 at = vec2(cell - frame_values.field_cells.xy) * edge + p + vec2(0.5 * edge);
    blade.position = vec3(at.x, 0.0, at.y);
    blade.facing = facing;
    return blade;
}

const float CELL_SPREAD_INSIDE = 0.7072; // render::ground_clipmap::CELL_SPREAD_INSIDE
const float CELL_SPREAD_OUTSIDE = 1.4143; // render::ground_clipmap::CELL_SPREAD_OUTSIDE

// The box of every blade of `cell` in any pose, relative to O: the relief at the cell's centre
// within the slope bound, padded by the longest blade.
void field_cell_bounds(ivec2 cell, out vec3 lo, out vec3 hi) {
    float edge = frame_values.field.x;
    vec2 corner = vec2(cell - frame_values.field_cells.xy) * edge;
    vec2 centre = corner + vec2(0.5 * edge);
    // `render::ground_clipmap::cell_spread`: the drawn ground interpolates the relief at its level's
    // vertices, which in levels of cells wider than half a block lie outside the cell; in cells of
    // two steps where the vertices slide onto the next level's mesh
    // (`render::ground_clipmap::drawn_step`).
    vec2 g;
    uint level = ground_level_at(centre, g);
    float step = ground_level_step(level);
    bool morphs = ground_edge_cells(g) - (0.5 * edge / step + 2.0) < float(GROUND_MORPH_END);
    float drawn = morphs ? 2.0 * step : step;
    float reach = CELL_SPREAD_INSIDE * edge + CELL_SPREAD_OUTSIDE * max(drawn - 0.5 * edge, 0.0);
    float spread = frame_values.field.y * reach;
    // `scene::tiles::blade_reach` of the tallest and widest blade: up, and across with the
    // density LOD's widest widening (`lod.w`).
    float up = TALLEST_BLADE + 0.5 * WIDEST_BLADE;
    float across = TALLEST_BLADE + 0.5 * WIDEST_BLADE * max(frame_values.lod.w, 1.0);
    float h = relief_height(centre);
    lo = vec3(corner.x - across, h - spread - FIELD_ROOT_SINK, corner.y - across);
    hi = vec3(corner.x + edge + across, h + spread + up, corner.y + edge + across);
}

// The box of the roots of a cell whose box `field_cell_bounds` gave (lo, hi: replaced): the
// cell's square, from the lowest root to the highest the relief's spread allows (the box's top
// less the tallest reach up, less the sink).
void field_cell_roots(BladeTile cell_box, out vec3 lo, out vec3 hi) {
    float up = TALLEST_BLADE + 0.5 * WIDEST_BLADE;
    float across = TALLEST_BLADE + 0.5 * WIDEST_BLADE * max(frame_values.lod.w, 1.0);
    lo = cell_box.min + vec3(across, 0.0, across);
    hi = cell_box.max - vec3(across, up + FIELD_ROOT_SINK, across);
}

// The blade of a visible entry of the cull's list (`visible_blade` of cull.glsl) and the index
// its force weights use: a stored blade, or in a block field (FLAG_BLOCKS) the ring slot (high
// bits) and the block's blade, at the root height the cull found. Shared by blade.vert and
// blade_pose.comp, so both place it alike.
BladeInstance visible_instance(uvec2 entry, out uint blade_index) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        ivec2 cell = frame_values.field_cells.xy + ring_cell(entry.x >> 16);
        blade_index = entry.x & 0xffffu;
        BladeInstance blade = field_blade(cell, blade_index);
        blade.position.y = visible_unpack(entry.y).x;
        return blade;
    }
    blade_index = entry.x;
    return blade_record(entry.x);
}

#endif
