// The GPU-driven cull (thesis §5.3, Zhang Xia §5.2, Belyaev §2.2, Jahrmann & Wimmer 2017), shared
// by its per-slot passes: cull_tiles.comp runs the tile tests of every slot of the rings around
// the centre tile (`scene::tiles::ring_cell`, so slots go near to far) and lists those with
// candidates, cull_count.comp counts what each listed slot draws (one workgroup per slot),
// cull_emit.comp writes the visible list from its verdicts (one workgroup per slot that draws);
// inside a tile, blades keep their stored (progressive) order. Every decision is a pure function of the tile, the
// blade and the frame's uniforms: the two passes agree, and the output does not depend on how
// threads are scheduled.
#ifndef MEADOW_CULL_GLSL
#define MEADOW_CULL_GLSL
#define FRAME_FROM_STORAGE
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/rings.glsl"

// The cull's own set (`SET_PASS`, `render::passes::cull::CullSetup`): its bindings are numbered
// here, for its four passes alone, and its Rust gives each resource by the block or variable name
// declared here (`vk::descriptor::SetLayout::write_named`). `Draws` is read by the per-blade
// passes too, in their own sets (blades/visible_buckets.glsl names it the same).
layout(set = SET_PASS, binding = 0, std430) buffer SlotCounts { uint slot_counts[]; };
layout(set = SET_PASS, binding = 1, std430) buffer Draws { uint draws[]; };
// Per frame in flight, host-visible: the frame's counts (`render::frame::slot::Frame`, its `cull_stats`).
layout(set = SET_PASS, binding = 2, std430) buffer CullStats { uint cull_stats[]; };
// Per candidate (from its slot's first verdict, `cull_alloc`; a slot's blades, then its own
// source's): x its bucket or NOT_DRAWN, y the visible entry's second word (`visible_scale`).
layout(set = SET_PASS, binding = 3, std430) buffer CullResults { uvec2 cull_results[]; };
const uint NOT_DRAWN = 0xffffffffu;
// Written by the tiles pass (cull_tiles.comp): the count pass's indirect dispatch (x, y, z, and
// x again), then per ring slot its first verdict, then per ring slot its candidates (the tile
// tests' result, read by the count and emit passes), then the slots with candidates in slot
// order, then per ring slot how many of its candidates are the blade tiles' (the rest are a
// draw-class set's own source's, `CLASS_SOURCE`: ranks from there on).
layout(set = SET_PASS, binding = 4, std430) buffer CullAlloc { uvec4 count_dispatch; uint alloc_words[]; };
uint verdict_base(uint slot) {
    return alloc_words[slot];
}
uint slot_candidates(uint slot) {
    return alloc_words[frame.cull_tiles.y + slot];
}
// The k-th slot with candidates.
uint listed_slot(uint k) {
    return alloc_words[2u * frame.cull_tiles.y + k];
}
// How many of a slot's candidates are blades of its tile (ranks 0 on); the rest, ranks from
// there on, are its own source's (`render::draw_class::CandidateSource`).
uint slot_blade_candidates(uint slot) {
    return alloc_words[3u * frame.cull_tiles.y + slot];
}

// Workgroup k of n visits item `spread(k, n)`: k * s mod n, with s near n / golden ratio and prime
// to n (a bijection of 0..n whose contiguous runs sample the whole range evenly). llvmpipe hands a
// dispatch's workgroups to its threads in contiguous blocks (`lp_cs_tpool_queue_task`: thread i
// takes the i-th n / threads of them, not one at a time), and the slots go near to far: a near
// slot holds up to a whole tile of candidates, a far one a few. In slot order the first thread got
// nearly all the work; spread, every block holds near and far slots alike. Only the order the
// workgroups run in changes: each still writes its own slot's words. k, s < n <= 65 536 ring
// slots (`render::field_gpu::max_blade_distance`, `render::scene_gpu::max_ring_slots`): k * s
// fits in 32 bits.
uint spread(uint k, uint n) {
    uint s = uint(float(n) * 0.618034);
    for (;;) {
        uint a = max(s, 1u);
        uint b = n;
        while (b != 0u) {
            uint r = a % b;
            a = b;
            b = r;
        }
        if (a == 1u) {
            break;
        }
        s++;
    }
    return n == 0u ? 0u : (k * max(s, 1u)) % n;
}

// A slot whose verdicts did not fit (`cull_alloc` ran out): it draws nothing.
const uint NO_ROOM = 0xffffffffu;

// The capacity scale (`THIN_WORD`) when the visible list holds every blade the blade tests keep.
const uint SCALE_ONE = 0xffffffffu;

// The capacity scale: when a frame's cull keeps more blades than the visible list holds, the scan
// thins each LOD bucket's sequence of kept blades (slots near to far, then stored order) evenly
// by s = `scale` / 2^32 < 1, a Bresenham rule over the whole sequence: entry k is kept when
// floor((k + 1) s) > floor(k s), and goes to position floor(k s). A bucket of n entries keeps
// floor(n s): a tile keeps its share whether it holds many of the bucket's blades or one, so the
// thinning is even over the view (no farthest-first hole). The scale is a function of the frame's
// counts alone: every run thins the same blades.
uint thin_position(uint k, uint scale) {
    uint high;
    uint low;
    umulExtended(k, scale, high, low);
    return scale == SCALE_ONE ? k : high;
}

bool thin_kept(uint k, uint scale) {
    return scale == SCALE_ONE || thin_position(k + 1u, scale) > thin_position(k, scale);
}

// Where candidate `rank`'s verdict goes: after its slot's first verdict (the tiles pass gives
// each slot its room by a prefix sum, in slot order, for either field).
uint verdict_index(uint base, uint rank) {
    return base + rank;
}

// The depth pyramid (hiz.comp writes it as a storage buffer), in the lavapipe profile read as
// texels: a vector gather on llvmpipe instead of a load per SIMD lane (`vk::buffer::TexelView`).
#ifdef TEXEL_TWINS
layout(set = SET_PASS, binding = 5) uniform samplerBuffer pyramid_texels;
float pyramid_texel(uint i) {
    return texelFetch(pyramid_texels, int(i)).x;
}
#else
layout(set = SET_PASS, binding = 5, std430) readonly buffer Pyramid { float pyramid[]; };
float pyramid_texel(uint i) {
    return pyramid[i];
}
#endif

// Belyaev §2.2 constants of the trinomial a1 + a2 d + a3 d²: with a1 = A1 and a3 = A1 / d0², the
// kept fraction is 1 out to about the full-density distance d0 (`lod.y`) and falls as 1/d² beyond,
// as the screen area of a square metre of ground does.
const float A1 = 0.25; // render::culling::A1
// Blades fade (narrow to nothing) over the top FADE_BAND of the kept fraction, so a blade the
// density LOD is about to drop is already gone when it is dropped: no popping.
const float FADE_BAND = 0.3; // render::culling::FADE_BAND
// Edge-on blades: |cos| of the angle between the view direction and the blade's width direction
// above which a blade is culled (Jahrmann & Wimmer 2017 use 0.9; meadow's blades twist in the wind,
// so only nearly exact edge-on views are dropped).
const float EDGE_ON = 0.97;

// The frame's cull toggles and LOD buckets (`frame.cull_lod`), read once per invocation by
// `read_cull_settings` before any test: a storage load is a loop over the SIMD lanes on llvmpipe,
// which the per-blade tests would otherwise repeat for every blade and toggle.
uvec4 cull_settings;

void read_cull_settings() {
    cull_settings = frame.cull_lod;
}

bool culling(uint bit) {
    return (cull_settings.z & bit) != 0u;
}

// The culling camera's planes, normalised: -w <= x, y <= w and z <= w (reversed infinite Z: the
// near plane; there is no far plane). Built once per invocation, not per test.
struct Frustum {
    vec4 planes[5];
};

Frustum culling_frustum() {
    mat4 m = frame_values.cull_view_proj;
    vec4 r0 = vec4(m[0][0], m[1][0], m[2][0], m[3][0]);
    vec4 r1 = vec4(m[0][1], m[1][1], m[2][1], m[3][1]);
    vec4 r2 = vec4(m[0][2], m[1][2], m[2][2], m[3][2]);
    vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    Frustum f;
    f.planes = vec4[5](r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 - r2);
    for (uint i = 0u; i < 5u; i++) {
        f.planes[i] /= length(f.planes[i].xyz);
    }
    return f;
}

bool box_in_frustum(Frustum f, vec3 lo, vec3 hi) {
    for (uint i = 0u; i < 5u; i++) {
        vec4 p = f.planes[i];
        vec3 corner = mix(lo, hi, greaterThanEqual(p.xyz, vec3(0.0)));
        if (dot(p.xyz, corner) + p.w < 0.0) {
            return false;
        }
    }
    return true;
}

bool sphere_in_frustum(Frustum f, vec3 centre, float radius) {
    bool inside = true;
    for (uint i = 0u; i < 5u; i++) {
        inside = inside && dot(f.planes[i].xyz, centre) + f.planes[i].w >= -radius;
    }
    return inside;
}

// Whether a sphere lies wholly behind this frame's terrain (the depth pyramid, hiz.comp, seen
// by the view's camera). Its screen rectangle is bounded conservatively: the centre's projection
// grown by what the radius can add at the sphere's nearest depth (w - r), and its nearest depth is
// near / (w - r) (reversed infinite Z: clip z is the near distance for every point). The rectangle
// is tested at the finest level where it spans at most two texels; larger ones are not tested.
bool occluded(vec3 centre, float radius) {
    vec4 c = frame_values.view_proj * vec4(centre, 1.0);
    float nearest_w = c.w - radius;
    if (nearest_w <= 1e-3) {
        return false;
    }
    vec2 ndc = c.xy / c.w;
    vec2 grow = (frame_values.tile_grid.zw * radius + abs(ndc) * radius) / nearest_w;
    vec2 lo = clamp((ndc - grow) * 0.5 + 0.5, 0.0, 1.0);
    vec2 hi = clamp((ndc + grow) * 0.5 + 0.5, 0.0, 1.0);
    float nearest_depth = c.z / nearest_w;
    // The finest level where the rectangle spans at most two texels (level l has a 4^l times
    // coarser grid), then its at most 3×3 texels, read without loops or branches: a SIMD lane
    // per blade on llvmpipe, where the loops' divergence cost more than the reads.
    float span0 = max(hi.x - lo.x, hi.y - lo.y) * float(PYRAMID_SIDE);
    uint level = span0 <= 2.0 ? 0u : uint(ceil(0.5 * log2(0.5 * span0)));
    level += span0 > 2.0 * float(1u << (2u * min(level, 15u))) ? 1u : 0u; // log2's rounding
    if (level >= PYRAMID_LEVELS) {
        return false;
    }
    uint side = PYRAMID_SIDE >> (2u * level);
    uint base = level == 0u ? 0u : (level == 1u ? PYRAMID_SIDE * PYRAMID_SIDE : PYRAMID_SIDE * PYRAMID_SIDE + side * side * 16u);
    uvec2 first = uvec2(min(lo * float(side), vec2(side - 1u)));
    uvec2 last = uvec2(min(hi * float(side), vec2(side - 1u)));
    float farthest = 1.0;
    for (uint dy = 0u; dy < 3u; dy++) {
        for (uint dx = 0u; dx < 3u; dx++) {
            uvec2 t = min(first + uvec2(dx, dy), last); // past `last`: a texel already read
            farthest = min(farthest, pyramid_texel(base + t.y * side + t.x));
        }
    }
    return nearest_depth < farthest;
}

// Belyaev §2.2: the fraction of blades kept at distance d, 1 - F(z, φ) before the clamp:
// ((1 - t)(n, r) + t) / (a1 + a2 d + a3 d²) with t = (1 - |(n, r)|)^α, α = 8, so contour areas
// ((n, r) near 0) keep their density. Above 1 near the camera (every blade kept).
// Belyaev's numerator (1 - t)(n, r) + t of `density_keep`.
float density_visible(float n_dot_r) {
    float t = 1.0 - abs(n_dot_r);
    t *= t;
    t *= t;
    t *= t; // (1 - |(n, r)|)^8 by squaring: exact, and what the CPU reference computes
    return (1.0 - t) * n_dot_r + t;
}

// The far field (`render::culling::far_field_distance`): past the distance where the survivors of
// a face-on patch reach the widening cap (`lod.w`), (1 - FADE_BAND / 2) keep = 1 / cap, the kept
// fraction falls as 1/d³ instead of 1/d².
float far_field(float d) {
    float d0 = frame_values.lod.y;
    return min(1.0, d0 * sqrt(frame_values.lod.w * (1.0 - 0.5 * FADE_BAND) / A1 - 1.0) / d);
}

float density_keep(float d, float n_dot_r) {
    float d0 = frame_values.lod.y;
    return density_visible(n_dot_r) / (A1 + A1 * (d * d) / (d0 * d0)) * far_field(d);
}

// An upper bound of `density_keep` over roots inside the box box_lo..box_hi, whose nearest point is
// `nearest` away, under normal n. A root p has (n, r) = n · (eye - p) / |eye - p|: n · (eye - p) is linear
// in p, so its range over the box is at two corners, and |eye - p| lies between the box's nearest
// and farthest distances. The numerator is 1 at (n, r) = 0, rises towards 0 from below and has
// one minimum above it (at about 0.24), so on an interval its largest value is at an end, or 1
// if the interval holds 0. A 2 % margin covers rounding (the bound only saves work; the blade
// test decides).
float density_keep_bound(vec3 n, vec3 box_lo, vec3 box_hi, float nearest) {
    vec3 eye = frame_values.cull_eye.xyz;
    bvec3 positive = greaterThanEqual(n, vec3(0.0));
    float most = dot(n, eye - mix(box_hi, box_lo, positive));
    float least = dot(n, eye - mix(box_lo, box_hi, positive));
    float near = max(nearest, 1e-3);
    float far = length(max(abs(eye - box_lo), abs(eye - box_hi)));
    float lo = clamp(least >= 0.0 ? least / far : least / near, -1.0, 1.0);
    float hi = clamp(most >= 0.0 ? most / near : most / far, -1.0, 1.0);
    float visible = lo <= 0.0 && hi >= 0.0 ? 1.0 : max(density_visible(lo), density_visible(hi));
    float d0 = frame_values.lod.y;
    return 1.02 * visible / (A1 + A1 * (nearest * nearest) / (d0 * d0)) * far_field(near);
}

// The tile of ring slot `slot`: a tile of the stored field, or in a block field (FLAG_BLOCKS) the
// cell around O's cell with the block's blades, its box only its square in x and z (the count
// and emit passes read no more of it; the tiles pass takes its heights from `slot_bounds`).
// False when the slot holds nothing.
bool slot_record(uint slot, out BladeTile tile, out ivec2 cell) {
    cell = frame_values.field_cells.xy + ring_cell(slot);
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        float edge = frame_values.field.x;
        vec2 corner = vec2(cell - frame_values.field_cells.xy) * edge;
        tile.min = vec3(corner.x, 0.0, corner.y);
        tile.max = vec3(corner.x + edge, 0.0, corner.y + edge);
        tile.first = 0u;
        tile.count = frame.params.y;
        return field_has_cell(cell);
    }
    int t = slot_tile(slot);
    if (t < 0) {
        return false;
    }
    // Member by member: glslang stores a buffer block's struct into a local one with an
    // OpStore whose types differ (their layouts do).
    tile.min = tiles[t].min;
    tile.first = tiles[t].first;
    tile.max = tiles[t].max;
    tile.count = tiles[t].count;
    if (FLOWER_SHARE != 0u) {
        // A tile's box is padded by its own blades' reach (`scene::tiles`): a flower on a short
        // blade stands taller (`scene::flowers`), up to the tallest blade and a head.
        float reach = TALLEST_BLADE + FLOWER_HEAD_REACH;
        tile.min -= vec3(reach, 0.0, reach);
        tile.max += vec3(reach);
    }
    return true;
}

// A slot's box for the tile tests and its most grass cover (`slot_record`'s tile): a block
// field's cell's bounds (`field_cell_bounds`), a stored tile's own box and full cover (its blades
// were scattered by the cover).
void slot_bounds(ivec2 cell, inout BladeTile tile, out float cover) {
    cover = 1.0;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        field_cell_bounds(cell, tile.min, tile.max, cover);
    }
}

// The ground's normal under a tile (Belyaev's n of §2.2).
vec3 tile_normal(BladeTile tile) {
    vec2 centre = 0.5 * (tile.min.xz + tile.max.xz);
    return ground_vertex_normal(centre);
}

// Blade `rank` of a slot's tile, placed (a block field's blade set in its cell, on the terrain).
BladeInstance tile_blade(BladeTile tile, ivec2 cell, uint rank) {
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        BladeInstance blade = field_blade(cell, rank);
        blade.position.y = ground_height(blade.position.xz) - FIELD_ROOT_SINK;
        return blade;
    }
    BladeInstance blade = blade_record(tile.first + rank);
    return blade;
}

// The visible list's first word for blade `rank` of a slot: the blade's index, or in a block
// field the slot (high 16 bits) and the block's blade (low 16 bits).
uint visible_blade(BladeTile tile, uint slot, uint rank) {
    return (RENDER_FLAGS & FLAG_BLOCKS) != 0u ? (slot << 16) | rank : tile.first + rank;
}

// The visible list's first word for candidate `rank` of a slot's own source (`CLASS_SOURCE`), in
// either field: the slot (high 16 bits) and the rank in the source (low 16 bits;
// `render::draw_class::MOST_SOURCE_CANDIDATES` bounds it). Its class's pass reads it with
// `source_entry` (common/field.glsl).
uint visible_source(uint slot, uint rank) {
    return (slot << 16) | rank;
}

// What the tile tests (frustum, distance, occlusion) leave of a tile: how many of its blades (a prefix) go to the blade tests.
uint tile_candidates(Frustum f, BladeTile tile, vec3 normal, float cover, out bool tile_visible) {
    vec3 eye = frame_values.cull_eye.xyz;
    float nearest = length(clamp(eye, tile.min, tile.max) - eye);
    tile_visible = tile.count > 0u;
    if (culling(CULL_FRUSTUM) && !box_in_frustum(f, tile.min, tile.max)) {
        tile_visible = false;
    }
    if (culling(CULL_DISTANCE) && nearest > frame_values.lod.x) {
        tile_visible = false;
    }
    if (tile_visible && culling(CULL_OCCLUSION)) {
        vec3 centre = 0.5 * (tile.min + tile.max);
        tile_visible = !occluded(centre, 0.5 * length(tile.max - tile.min));
    }
    if (!tile_visible) {
        return 0u;
    }
    // A block field's cell keeps the ranks under its cover at each root (`blade_bucket`): no
    // more than its most cover's prefix (`slot_bounds`), and none where it has none (bare ground
    // is not visited).
    float most = cover;
    if (most <= 0.0) {
        tile_visible = false;
        return 0u;
    }
    if (!culling(LOD_DENSITY)) {
        return uint(clamp(ceil(most * float(tile.count) - 0.5) + 1.0, 0.0, float(tile.count)));
    }
    // Blade r is kept when (r + 0.5) / count < keep: a prefix (one more for rounding). The bound
    // holds over the roots (the blade test measures from the root): a block field's cell gives
    // its roots' box, tighter than the tile box by the blades' reach (up, and across with the
    // widening: at the unbounded field's default view the count pass went from 12.7 to 11.7 ms,
    // the blades it keeps unchanged). A stored tile's box is padded per tile (`scene::tiles`),
    // so its bound keeps the whole box.
    vec3 lo = tile.min;
    vec3 hi = tile.max;
    if ((RENDER_FLAGS & FLAG_BLOCKS) != 0u) {
        field_cell_roots(tile, lo, hi);
    }
    float keep = min(density_keep_bound(normal, lo, hi, length(clamp(eye, lo, hi) - eye)), most);
    return uint(clamp(ceil(keep * float(tile.count) - 0.5) + 1.0, 0.0, float(tile.count)));
}

// Segments of LOD bucket `b` of the blade class.
uint bucket_segments(uint b) {
    return ((cull_settings.y >> (4u * b)) & 15u) + 1u;
}

// The draw classes (`render::draw_class`, `cull_classes` of the frame): every class's buckets
// follow each other in the cull's bucket space, the blade class's LOD buckets first. A class's
// selection (the count pass's `class_bucket`) sorts a candidate into one of its buckets; the
// scan, the emit and the draws are the same for every class.
uint draw_buckets() {
    return frame.cull_classes.x;
}

// The first bucket of further class `k` (1 the first class after the blades).
uint class_first_bucket(uint k) {
    return frame.cull_classes.w >= k && k >= 1u ? frame.cull_class_first[k - 1u] : draw_buckets();
}

// Whether bucket `b`'s class draws far to near (blended classes): its slots' entries go in the
// visible list, and its rows, farthest first.
bool bucket_far_to_near(uint b) {
    return ((frame.cull_classes.y >> b) & 1u) != 0u;
}

// Whether bucket `b`'s class draws a row per visible tile (`render::draw_rows`).
bool bucket_rows(uint b) {
    return TILE_ROWS_CAPACITY > 0u && ((frame.cull_classes.z >> b) & 1u) != 0u;
}

// The indexed draw of one instance of bucket `b` (BLADES_PER_INSTANCE entries): its index count
// and its first index. The blade class's from its segments, in the blade pass's index buffer
// (`scene::bezier::bucket_indices`, its buckets' lists one after another); a further class's from
// the frame (`render::draw_class::DrawClass::bucket_draw`), in its own pass's.
uvec2 bucket_draw(uint b) {
    if (b < cull_settings.x) {
        uint first = 0u;
        for (uint k = 0u; k < b; k++) {
            first += 3u * bucket_blade_triangles(bucket_segments(k)) * BLADES_PER_INSTANCE;
        }
        return uvec2(3u * bucket_blade_triangles(bucket_segments(b)) * BLADES_PER_INSTANCE, first);
    }
    uvec4 pair = frame.cull_bucket_draws[b / 2u];
    return (b & 1u) == 0u ? pair.xy : pair.zw;
}

// The blade tests. Returns the blade's LOD bucket, or -1 with the first test it failed in
// `failed` (a `STAT_*` index: the counts after that test do not include it). `scale` is
// (fade, widening) for the vertex shader. `seen_from_all_sides`: no edge-on test (a plant of a
// further class that shows from every side, as a flower's head).
int plant_bucket(Frustum f, BladeInstance blade, uint rank, uint count, vec3 normal, bool seen_from_all_sides, out uint failed, out vec2 scale) {
    vec3 to_eye = frame_values.cull_eye.xyz - blade.position;
    float d = max(length(to_eye), 1e-3);
    scale = vec2(1.0);
    failed = 0u;
    // The ground's cover (`scene::cover`): a block field keeps the ranks under it at the root, a
    // thinning that widens no survivor (a stored field's blades were scattered by it). Counted
    // with the density LOD's (`STAT_DENSITY`).
    if (GROUND_COVER != 0u && (RENDER_FLAGS & FLAG_BLOCKS) != 0u
        && (float(rank) + 0.5) / float(count) >= ground_cover(blade.position.xz)) {
        failed = STAT_DENSITY;
        return -1;
    }
    if (culling(LOD_DENSITY)) {
        float keep = density_keep(d, dot(normal, to_eye / d));
        float w = (float(rank) + 0.5) / float(count);
        if (w >= keep) {
            failed = STAT_DENSITY;
            return -1;
        }
        // Fading blades cover half of a full one on average (their width shrinks linearly, their
        // height stays: blade_place.glsl says why): the
        // survivors widen so that the expected covered area stays that of the whole tile.
        float fade = clamp((keep - w) / (FADE_BAND * keep), 0.0, 1.0);
        float covered = min(keep * (1.0 - 0.5 * FADE_BAND), 1.0);
        scale = vec2(fade, min(1.0 / covered, frame_values.lod.w));
    }
    // The far field's band (`render::far_field`, a dither): from the band's start to the
    // blade range the blades thin out, each at its own threshold (rank times the golden ratio,
    // mod 1: spread evenly over any run of ranks, apart from the density LOD's prefix), while the
    // far field's plants fade in (far.frag). Unwidened: the far field takes the coverage over.
    // Measured from the band's eye (`render::far_rings::BandEye`, the hysteresis), the ramp
    // ending a leash short of the blade range, so that it ends before the distance test.
    float band_start = uintBitsToFloat(frame.params.z);
    if (band_start > 0.0) {
        float ramp = far_band_ramp(distance(blade.position, frame_values.band_eye.xyz), band_start);
        if (fract(float(rank) * 0.61803398875) < ramp) {
            failed = STAT_DENSITY;
            return -1;
        }
    }
    float reach = blade.height + 0.5 * blade.width * scale.x * scale.y;
    if (culling(CULL_FRUSTUM) && !sphere_in_frustum(f, blade.position, reach)) {
        failed = STAT_FRUSTUM;
        return -1;
    }
    if (culling(CULL_DISTANCE) && d - reach > frame_values.lod.x) {
        failed = STAT_FRUSTUM;
        return -1;
    }
    if (culling(CULL_ORIENTATION) && !seen_from_all_sides) {
        vec2 across = vec2(cos(blade.facing), -sin(blade.facing));
        vec2 view = to_eye.xz / max(length(to_eye.xz), 1e-6);
        if (abs(dot(view, across)) > EDGE_ON) {
            failed = STAT_ORIENTATION;
            return -1;
        }
    }
    if (culling(CULL_OCCLUSION) && occluded(blade.position, reach)) {
        failed = STAT_OCCLUSION;
        return -1;
    }
    uint buckets = cull_settings.x;
    uint bucket = 0u;
    if (culling(LOD_SEGMENTS)) {
        // Projected height in pixels; the fewest segments that keep each under `lod.z` pixels.
        // A fading blade counts as shorter by its fade: it keeps its height but is narrowing to
        // nothing, and its curve matters less than its width (full height here drew 11 % more
        // triangles at 1M blades for no measured gain in the 8x8 difference from brute force).
        float pixels = scale.x * blade.height * frame_values.cull_eye.w / d;
        float needed = pixels / frame_values.lod.z;
        for (uint b = 1u; b < buckets; b++) {
            if (float(bucket_segments(b)) >= needed) {
                bucket = b;
            }
        }
    }
    return int(bucket);
}

// The blade tests of a blade (`plant_bucket`, with the edge-on test).
int blade_bucket(Frustum f, BladeInstance blade, uint rank, uint count, vec3 normal, out uint failed, out vec2 scale) {
    return plant_bucket(f, blade, rank, count, normal, false, failed, scale);
}

#endif
