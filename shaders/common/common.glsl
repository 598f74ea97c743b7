// Shared GPU data layout. The Rust mirrors are `render::uniforms::FrameUniforms` and
// `scene::blades::BladeInstance`; their sizes and offsets are asserted at compile time in Rust and
// read back through `blade_readback.comp` in the tests.
#ifndef MEADOW_COMMON_GLSL
#define MEADOW_COMMON_GLSL
#include "common/shared.glsl"
#include "generated/spec_ids.glsl"

// Per-frame constants (std140, 992 bytes).
struct FrameUniforms {
    mat4 view_proj;         // world -> clip (reversed infinite Z, Vulkan y down)
    vec4 camera_position;   // xyz eye, w simulation time (s)
    vec4 sun_direction;     // xyz unit vector towards the sun, w unused
    vec4 sky_color;         // rgb linear sky, w fog density (1/m)
    vec4 terrain;           // a stored terrain: x grid origin (x = z), y cell size (m) (the CPU's cull mirror); a block field: y the innermost wind level's cluster edge; the ground itself is `ground`
    uvec4 params;           // x segments, y blade count, z the far field's band start (m, f32 bits; 0: no far field, `render::far_field`), w a block field's view distance, where its haze ends (m, f32 bits; 0: stored blades) (the ground's cells: `ground.x`)
    uvec4 wind_counts;      // x point sources, y colliders (emitters after the sources), z cluster corners per side, w wind levels
    mat4 cull_view_proj;    // world -> clip of the culling camera (the view's, or a frozen one)
    vec4 cull_eye;          // xyz culling camera position, w pixels per metre at 1 m (viewport height / (2 tan(fov_y / 2)))
    vec4 lod;               // x blade range (m, `render::culling::Culling::blade_range`), y full-density distance (m, LOD scale applied), z pixels per segment (LOD scale applied), w largest widening
    vec4 tile_grid;         // x origin (x = z), y tile edge (m), z and w the view's projection P00 and P11 (occlusion)
    uvec4 cull_tiles;       // x a stored field's tiles per side, y ring slots, z centre tile x, w centre tile z
    uvec4 cull_lod;         // x LOD buckets, y their segment counts minus 1 (4 bits each, bucket 0 lowest), z CULL_* / LOD_* bits, w entries of the visible list
    // Block fields: positions are relative to an origin O, the corner of the block cell under
    // the camera (the camera, the view matrix and the emitters too).
    vec4 relief_waves[RELIEF_WAVES]; // xy wave vector (2π / wavelength), z amplitude, w phase
    vec4 relief_phases[RELIEF_WAVES / 2u]; // sin, cos of u_k · O + φ_k, two waves per vec4
    ivec4 field_cells;      // xy O's cell, z cells of a bounded field per side (0: unbounded), w unused
    vec4 field;             // x block edge (m), y relief slope bound, zw the force corners' origin relative to O
    uvec4 ground;           // the ground's clipmap (`render::ground`, common/ground.glsl): x cells per side of a level, z levels, y the slope limit (radians, f32 bits; 0: none), w its soft edge's width (radians, f32 bits)
    ivec4 relief_cycles[RELIEF_WAVES / 2u]; // per wave its whole periods in the world's (m, n), two waves per vector
    vec4 ground_levels[CAMERA_GRID_MAX_LEVELS]; // per clipmap level: xy its window's first vertex relative to O, z its cell edge, w the run (m) its texels' rise is over
    ivec4 ground_windows[CAMERA_GRID_MAX_LEVELS]; // per level: xy the window's toroidal base, zw the source's (the relief's: its first vertex in half-metres on the world's period)
    // The cull's draw classes (`render::draw_class`): the blade class's buckets first (`cull_lod.x`),
    // then each further class's.
    uvec4 cull_classes;     // x buckets of every class, y buckets drawn far to near (a bit each), z buckets drawn a row per visible tile, w further classes
    uvec4 cull_class_first; // the first bucket of further class 1, 2, 3, 4
    uvec4 cull_bucket_draws[MAX_LOD_BUCKETS / 2u]; // per bucket of a further class: its draw's index count per instance and first index, two buckets per vector
    vec4 band_eye;          // xyz the point the far field's band is measured from (`render::far_rings::BandEye`: the culling camera on a leash), w the leash (m)
    uvec4 cull_room;        // x verdicts cull_results holds, y most candidates a draw-class set's own source adds to a slot (`render::draw_class::CandidateSource`), zw unused
};


// How the blades are animated is fixed per pipeline by specialization constants, not read from
// uniforms: llvmpipe (and most GPUs) compile a uniform branch into masked code that pays for every
// path, so each configuration gets its own pipeline with the other paths compiled out.
// `render::specialization::Specialization` fills them by name; build.rs numbers the ids
// (`SPEC(NAME)`, generated/spec_ids.glsl) and the codes are in shared.glsl.
layout(constant_id = SPEC(ANIMATION_MODE)) const uint ANIMATION_MODE = MODE_STATIC;
layout(constant_id = SPEC(SMOOTHING)) const uint SMOOTHING = 0u;
layout(constant_id = SPEC(KEYFRAME_ENCODING)) const uint KEYFRAME_ENCODING = 1u;
layout(constant_id = SPEC(ATTENUATION)) const uint ATTENUATION = ATTENUATION_CLUSTER;
layout(constant_id = SPEC(REPRESENTATION)) const uint REPRESENTATION = REPRESENTATION_LEVELS;
layout(constant_id = SPEC(RENDER_FLAGS)) const uint RENDER_FLAGS = 0u; // FLAG_* bits
// Blade geometry (`scene::bezier::Batching`): with constants, the vertex shader's divisions by
// the strip length become multiplications, and one blade per instance needs none at all.
// Arrays of levels are sized by MAX_SEGMENTS + 1, never by SEGMENTS.
layout(constant_id = SPEC(SEGMENTS)) const uint SEGMENTS = 4u;
layout(constant_id = SPEC(BLADES_PER_INSTANCE)) const uint BLADES_PER_INSTANCE = 1u;
layout(constant_id = SPEC(ENCODE_SRGB)) const uint ENCODE_SRGB = 1u;
layout(constant_id = SPEC(MODEL_SEGMENTS)) const uint MODEL_SEGMENTS = 4u;
// The ground's clipmap (`render::ground`, common/ground.glsl): cells per side of a level and the
// levels held. Constants, not the frame's `ground`: they decide which level a point reads, and
// lavapipe compiles a variant of a compute pipeline per value of a uniform that decides a branch
// (profile.glsl's rule), while the storage twin costs a load per SIMD lane. A change of the view
// distance rebuilds the pipelines.
layout(constant_id = SPEC(GROUND_CELLS)) const uint GROUND_CELLS = 80u;
layout(constant_id = SPEC(GROUND_LEVELS)) const uint GROUND_LEVELS = 1u;
// Whether the ground's cover thins the grass and tints the terrain (`scene::cover`): without it
// the cover is 1 everywhere and its reads are compiled out.
layout(constant_id = SPEC(GROUND_COVER)) const uint GROUND_COVER = 0u;
// A block field's clump size in millimetres (`scene::clumps`, `--clumps`; 0: no clumps).
layout(constant_id = SPEC(CLUMP_SIZE_MM)) const uint CLUMP_SIZE_MM = 0u;
// The share of candidate blades the flowers claim under full green and grass, an f32's bits
// (`scene::flowers`, `--flowers`; 0: no flowers).
layout(constant_id = SPEC(FLOWER_SHARE)) const uint FLOWER_SHARE = 0u;

// Model level m0 below strip level `level` of a `segments`-segment strip, and how far towards
// m0 + 1 it lies (0 when `segments` divides MODEL_SEGMENTS). The pose pass writes, and the levels
// pass and blade.vert read, the model levels this names.
uint model_level(uint level, uint segments, out float frac) {
    if ((MODEL_SEGMENTS % segments) == 0u) {
        frac = 0.0;
        return level * (MODEL_SEGMENTS / segments);
    }
    float at = float(level * MODEL_SEGMENTS) / float(segments);
    frac = at - floor(at);
    return uint(at);
}
// Invocations of the cull's count and emit workgroups (one per ring slot, or per slot that draws): the device's
// subgroup size (`render::passes::cull::workgroup_size`), so a slot's tile tests run once per subgroup;
// on llvmpipe a 64-wide group ran them 8 times and cost 13 ms more at 1M blades.
layout(constant_id = SPEC(CULL_GROUP)) const uint CULL_GROUP = 64u;
layout(constant_id = SPEC(MSAA_SAMPLES)) const uint MSAA_SAMPLES = 1u;
// With the solid outline (a LOD bucket's pipeline, `render::recording::bucket_dispatch::bucket_constants`):
// the strip of SEGMENTS segments widened to cover the alpha-tested outline's area, and its l^6
// scaled so its area-weighted mean is brute force's (`scene::alpha`).
layout(constant_id = SPEC(STRIP_AREA)) const float STRIP_AREA = 1.0;
layout(constant_id = SPEC(STRIP_L6)) const float STRIP_L6 = 1.0;
// The blade class's rows (`render::draw_rows`): 0 draws each LOD bucket once; else one draw per
// visible tile and bucket inside a multi-draw-indirect, this many rows per bucket (the ring
// slots the cull holds; cull/tile_rows.glsl gives the layout).
layout(constant_id = SPEC(TILE_ROWS_CAPACITY)) const uint TILE_ROWS_CAPACITY = 0u;
// The LOD bucket a blade pipeline draws (`render::passes::blades`), for its per-tile records.
layout(constant_id = SPEC(LOD_BUCKET)) const uint LOD_BUCKET = 0u;
// Brute force draws strips, joined by repeating a strip's first and last vertices. With the cull
// (FLAG_CULLED), the LOD buckets draw indexed triangle lists instead (`scene::bezier::BladeMesh`):
// no joins, and a blade whose outline is geometry (FLAG_SOLID_OUTLINE: zero width at the tip)
// ends in one tip vertex, its top segment one triangle.
const uint TIP_VERTICES = (RENDER_FLAGS & FLAG_SOLID_OUTLINE) != 0u ? 1u : 2u;
const uint STRIP_LEAD = (RENDER_FLAGS & FLAG_CULLED) == 0u && BLADES_PER_INSTANCE > 1u ? 1u : 0u; // repeats of a strip's first vertex
const uint STRIP_STRIDE = (RENDER_FLAGS & FLAG_CULLED) != 0u
    ? 2u * SEGMENTS + TIP_VERTICES
    : 2u * (SEGMENTS + 1u) + 2u * STRIP_LEAD; // vertices per blade

// Triangles of one blade of `segments` segments in a LOD bucket's list (a collapsed tip has one).
uint bucket_blade_triangles(uint segments) {
    return 2u * segments - (2u - TIP_VERTICES);
}

// Per-blade cluster record (std430, 8 bytes): eq. 3.7 weights precomputed.
struct BladeCluster {
    uint corner;            // corner of the cluster with the smallest x and z
    uint weights;           // unorm8 x4: (x0,z0) (x1,z0) (x0,z1) (x1,z1)
};

// One blade (std430, 32 bytes).
struct BladeInstance {
    vec3 position;          // root, world space
    float facing;           // radians about +y; normal = (sin, 0, cos)
    float height;           // backbone length (m)
    float width;            // m
    float stiffness;        // relative joint stiffness
    uint variation;         // unorm8 x4: hue, brightness, lean, spare (the debug view's force in blade.frag)
};

// One tile of blades (std430, 32 bytes, `scene::tiles::BladeTile`).
struct BladeTile {
    vec3 min;               // bounds of every blade of the tile in any pose
    uint first;             // first blade
    vec3 max;
    uint count;             // blades
};

const float PI = 3.14159265;

#endif
