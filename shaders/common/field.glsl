// Block fields (`scene::field`, Belyaev §2.1): the relief and the blades of the cells around the
// origin O, every position relative to O (FrameUniforms' field part), so the numbers stay small
// wherever the camera is. Mirrors `scene::field` on the CPU.
#ifndef MEADOW_FIELD_GLSL
#define MEADOW_FIELD_GLSL
#include "common/camera_grid.glsl"
#include "common/rings.glsl"
#include "common/ground.glsl"
#include "common/clumps.glsl"

const float TALLEST_BLADE = 0.55; // scene::blades::TALLEST
const float WIDEST_BLADE = 0.016; // scene::blades::WIDEST

// Roots are sunk this far below the drawn terrain (as a stored field's, `scene::blades::ROOT_SINK`).
const float FIELD_ROOT_SINK = 0.01;

// How far a flower's head reaches past its stem's tip (`scene::flowers`).
const float FLOWER_HEAD_REACH = 0.06; // scene::flowers::HEAD_REACH_M

// How far past its root a plant reaches, up and across (`scene::tiles::blade_reach` of the tallest
// and widest blade, across with the density LOD's widest widening, `lod.w`), or with flowers
// (FLOWER_SHARE) a head past the tallest stem, which no widening widens.
float plant_up() {
    return TALLEST_BLADE + (FLOWER_SHARE != 0u ? max(FLOWER_HEAD_REACH, 0.5 * WIDEST_BLADE) : 0.5 * WIDEST_BLADE);
}

float plant_across() {
    float widest = 0.5 * WIDEST_BLADE * max(frame_values.lod.w, 1.0);
    return TALLEST_BLADE + (FLOWER_SHARE != 0u ? max(FLOWER_HEAD_REACH, widest) : widest);
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

// The world's period in half-metres, the lattice the relief's clipmap texels are evaluated on
// (`render::ground_clipmap::PERIOD_HALF_METRES`: a block is 8 half-metres).
const uint PERIOD_HALF_METRES = uint(PERIOD_CELLS) * 8u;

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
    if (CLUMP_SIZE_MM != 0u) {
        // In clumps (`scene::clumps`): on the world's lattice, the cell modulo the world's period.
        ivec2 wrapped = ((cell % PERIOD_CELLS) + PERIOD_CELLS) % PERIOD_CELLS;
        blade = clumped(blade, vec2(wrapped) * edge + p + vec2(0.5 * edge));
    }
    return blade;
}

const float CELL_SPREAD_INSIDE = 0.7072; // render::ground_clipmap::CELL_SPREAD_INSIDE
const float CELL_SPREAD_OUTSIDE = 1.4143; // render::ground_clipmap::CELL_SPREAD_OUTSIDE

#ifndef GROUND_WRITER

// The box of every blade of `cell` in any pose, relative to O: the drawn ground at the cell's
// centre (the clipmap's, whatever the ground's source) within twice the spread the slope bound
// allows the drawn ground from the ground itself (each of the cell's points and its centre lies
// within one spread of the ground at the centre) and within the clipmap's tiles' range under the
// cell (`ground_tile_bounds`), padded by the longest blade;
// and the most grass cover at its roots, from the same tiles (none: no grass).
void field_cell_bounds(ivec2 cell, out vec3 lo, out vec3 hi, out float cover) {
    float edge = frame_values.field.x;
    vec2 corner = vec2(cell - frame_values.field_cells.xy) * edge;
    vec2 centre = corner + vec2(0.5 * edge);
    // `render::ground_clipmap::cell_spread`: the drawn ground interpolates the relief at its level's
    // vertices, which in levels of cells wider than half a block lie outside the cell; in cells of
    // two steps where the vertices slide onto the next level's mesh
    // (`render::ground_clipmap::drawn_step`).
    vec2 g;
    uvec2 shape = ground_shape();
    uint level = ground_level_at(centre, shape, g);
    float step = ground_level_step(level);
    bool morphs = ground_edge_cells(g, shape.x) - (0.5 * edge / step + 2.0) < float(GROUND_MORPH_END);
    float drawn = morphs ? 2.0 * step : step;
    float reach = CELL_SPREAD_INSIDE * edge + CELL_SPREAD_OUTSIDE * max(drawn - 0.5 * edge, 0.0);
    float spread = 2.0 * frame_values.field.y * reach;
    // `scene::tiles::blade_reach` of the tallest and widest blade: up, and across with the
    // density LOD's widest widening (`lod.w`).
    float up = plant_up();
    float across = plant_across();
    float h = ground_height(centre);
    vec2 range = vec2(h - spread, h + spread);
    // The ground source's tiles under the cell's square (`ground_tile_bounds`: the drawn ground,
    // at every level that draws a root of it): another bound, a millimetre for the f32 heights.
    // (FLAG_GROUND_BOUNDS: off, the slope's spread alone: `render::culling::Culling`'s ground_bounds.)
    vec4 tiles = ground_tile_bounds(corner, corner + vec2(edge));
    if ((RENDER_FLAGS & FLAG_GROUND_BOUNDS) != 0u) {
        range = vec2(max(range.x, tiles.x - 0.001), min(range.y, tiles.y + 0.001));
    }
    cover = GROUND_COVER != 0u ? tiles.z : 1.0;
    lo = vec3(corner.x - across, range.x - FIELD_ROOT_SINK, corner.y - across);
    hi = vec3(corner.x + edge + across, range.y + up, corner.y + edge + across);
}

#endif

// The box of the roots of a cell whose box `field_cell_bounds` gave (lo, hi: replaced): the
// cell's square, from the lowest root to the highest the ground's bounds allow (the box's top
// less the tallest reach up, less the sink).
void field_cell_roots(BladeTile cell_box, out vec3 lo, out vec3 hi) {
    float up = plant_up();
    float across = plant_across();
    lo = cell_box.min + vec3(across, 0.0, across);
    hi = cell_box.max - vec3(across, up + FIELD_ROOT_SINK, across);
}

// A stored field's tile of ring slot `slot` (the rings around the centre tile,
// `frame.cull_tiles`), or -1 when the slot lies outside the grid: the cull's, and a draw-class
// source's pass's (`source_entry`).
int slot_tile(uint slot) {
    ivec2 cell = ivec2(frame.cull_tiles.zw) + ring_cell(slot);
    int n = int(frame.cull_tiles.x);
    if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(n)))) {
        return -1;
    }
    return cell.y * n + cell.x;
}

// A visible entry of a draw-class set's own source (`visible_source` of cull.glsl,
// `render::draw_class::CandidateSource`): its ring slot, and its rank in the source in `rank`.
// The class's pass finds its candidate from the slot: a block field's cell
// (`frame_values.field_cells.xy + ring_cell(slot)`) or a stored field's tile (`slot_tile`).
uint source_entry(uvec2 entry, out uint rank) {
    rank = entry.x & 0xffffu;
    return entry.x >> 16;
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
