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

// The terrain grid (terrain.vert): vertex v lies at v * step + offset relative to O, the offset
// keeping the vertices on the world's lattice (`render::field_gpu::terrain_grid_offset`).
vec2 terrain_grid_offset() {
    return frame_values.terrain.zw;
}

// Whether the far terrain is drawn in cells of two grid steps (`render::field_gpu::terrain_coarsens`):
// when a block spans an even number of cells.
bool terrain_coarsens() {
    return 2.0 * frame_values.terrain.x <= frame_values.field.x;
}

// Height of the drawn terrain (the relief at the grid's vertices, flat between them, split as
// terrain.vert splits a cell) from the heights of the cell's four vertices.
float terrain_mesh_height(vec2 f, float h00, float h10, float h01, float h11) {
    return f.x >= f.y ? h00 + f.x * (h10 - h00) + f.y * (h11 - h10) : h00 + f.y * (h01 - h00) + f.x * (h11 - h01);
}

#ifndef RELIEF_GRID_WRITER
// Grid vertex v (clamped to the grid): the drawn terrain's height there and the relief's normal.
// The texel sits in the vertex's slot of the camera grid (the window's base in
// `relief_grid.xy`); from TERRAIN_MORPH_CELLS to TERRAIN_FINE_CELLS (Chebyshev, from the grid's
// centre) an odd vertex's height slides onto the coarse mesh's, and past them it is that mesh,
// so fine and coarse chunks meet without cracks and the cull's roots, interpolating this grid,
// sit on the terrain as drawn (`render::field_gpu::terrain_morph`, CDLOD's morph by the grid's
// place). The normal stays the relief's.
vec4 relief_vertex(ivec2 v) {
    int n = int(FIELD_TERRAIN_CELLS) + 1;
    v = clamp(v, ivec2(0), ivec2(n - 1));
    uvec3 dims = uvec3(n, 1, n);
    uvec3 base = uvec3(frame_values.relief_grid.x, 0u, frame_values.relief_grid.y);
    vec4 t = relief_texel(int(camera_grid_slot(uvec3(v.x, 0, v.y), base, dims)));
    float h = t.x;
    if (terrain_coarsens() && ((v.x | v.y) & 1) != 0) {
        ivec2 d = abs(v - ivec2(FIELD_TERRAIN_CELLS / 2u));
        float band = float(TERRAIN_FINE_CELLS - TERRAIN_MORPH_CELLS);
        float k = clamp(float(max(d.x, d.y) - int(TERRAIN_MORPH_CELLS)) / band, 0.0, 1.0);
        if (k > 0.0) {
            h = mix(h, t.y, k);
        }
    }
    return vec4(h, t.z, sqrt(max(1.0 - t.z * t.z - t.w * t.w, 0.0)), t.w);
}

// The grid cell under `p` (relative to O), clamped to the grid, and where `p` lies in it.
ivec2 relief_cell(vec2 p, out vec2 f) {
    vec2 g = (p - terrain_grid_offset()) / frame_values.terrain.x;
    ivec2 c = clamp(ivec2(floor(g)), ivec2(0), ivec2(int(FIELD_TERRAIN_CELLS) - 1));
    f = clamp(g - vec2(c), vec2(0.0), vec2(1.0));
    return c;
}

// Height of the drawn terrain at `p` (relative to O): the grid's heights at the corners of its
// cell, split as terrain.vert splits it, so a root sits on the terrain as drawn.
float field_ground_height(vec2 p) {
    vec2 f;
    ivec2 c = relief_cell(p, f);
    float h00 = relief_vertex(c).x;
    float h10 = relief_vertex(c + ivec2(1, 0)).x;
    float h01 = relief_vertex(c + ivec2(0, 1)).x;
    return terrain_mesh_height(f, h00, h10, h01, relief_vertex(c + ivec2(1, 1)).x);
}

// The relief's normal at `p`: the grid vertices' normals, interpolated bilinearly.
vec3 field_ground_normal(vec2 p) {
    vec2 f;
    ivec2 c = relief_cell(p, f);
    vec3 bottom = mix(relief_vertex(c).yzw, relief_vertex(c + ivec2(1, 0)).yzw, f.x);
    vec3 top = mix(relief_vertex(c + ivec2(0, 1)).yzw, relief_vertex(c + ivec2(1, 1)).yzw, f.x);
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

const float CELL_SPREAD_INSIDE = 0.7072; // render::field_gpu::CELL_SPREAD_INSIDE
const float CELL_SPREAD_OUTSIDE = 1.4143; // render::field_gpu::CELL_SPREAD_OUTSIDE

// The box of every blade of `cell` in any pose, relative to O: the relief at the cell's centre
// within the slope bound, padded by the longest blade.
void field_cell_bounds(ivec2 cell, out vec3 lo, out vec3 hi) {
    float edge = frame_values.field.x;
    vec2 corner = vec2(cell - frame_values.field_cells.xy) * edge;
    vec2 centre = corner + vec2(0.5 * edge);
    // `render::field_gpu::cell_spread`: the drawn terrain interpolates the relief at the grid's
    // vertices, which past 156 m of view distance lie outside the cell.
    // The drawn cells' edge: two steps where the grid's vertices slide onto the far terrain's
    // coarse mesh (`render::field_gpu::drawn_step`).
    float step = frame_values.terrain.x;
    vec2 g = abs((centre - terrain_grid_offset()) / step - vec2(float(FIELD_TERRAIN_CELLS / 2u)));
    bool morphs = terrain_coarsens() && max(g.x, g.y) + 0.5 * edge / step + 2.0 > float(TERRAIN_MORPH_CELLS);
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
