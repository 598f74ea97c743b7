// The far field (`render::far_field`, issue #37): Zhang Xia's billboards (§4.1) or Pelzer's stars
// (§7.3) past the blades, on rings of a world lattice whose step doubles per ring (eq. 8–9).
// Shared by the placement (far_place.comp) and the draw (far.vert, far.frag). Its own set: the
// parameters (`FarParams`), the placed plants (`FarPlants`) and their draw (`FarDraw`), by name.
// The includer includes common/bindings.glsl first.
#ifndef MEADOW_FAR_FIELD_GLSL
#define MEADOW_FAR_FIELD_GLSL

const uint FAR_TIP_TABLE = 32u;        // render::far_field::TIP_TABLE_SIZE
const float FAR_TIP_MAX = 24.0;        // render::far_field::TIP_TABLE_MAX (m/s)
const uint FAR_RING_SIDE = 36u;        // render::far_rings::RING_SIDE
const float FAR_WIDTH_STEPS = 1.0;     // render::far_field::WIDTH_STEPS
const float FAR_NEAR_WIDTH = 0.5;      // render::far_field::NEAR_WIDTH
const float FAR_BLOCK = 4.0;           // scene::field::BLOCK_SIZE
const uint FAR_TILES = 4u;             // render::far_field::atlas::TILES
const uint FAR_MIPS = 9u;              // render::far_field::atlas::MIPS
const float FAR_TILE_WIDTH = 1.0;      // render::far_field::atlas::TILE_WIDTH_M
const float FAR_TILE_HEIGHT = 0.6;     // render::far_field::atlas::TILE_HEIGHT_M
const vec2 FAR_TILE_TEXELS = vec2(512.0, 256.0); // render::far_field::atlas::TILE_TEXELS
const uint FAR_MESH_BILLBOARDS = 0u;   // six half-planes round the axis
const uint FAR_MESH_STARS = 1u;        // three crossed quads
// The share of a ring over which the plants the next ring's lattice drops fade out (its outer half).
const float FAR_RING_FADE = 0.5;
// A far rectangle whose normal's cosine to the view (across the ground) is under this is not
// drawn: seen within 15° of edge-on.
const float FAR_EDGE_ON = 0.26;
// A far rectangle's fade in the band is decided per stretch this wide (m): about a blade's place.
const float FAR_STRETCH = 0.25;

struct FarParams {
    vec4 rings;   // x ring 0's inner Chebyshev distance, y its lattice step, z the band's start (m),
                  // w the flower tiles' share (render::far_field::atlas; 0: no flowers)
    vec4 reach;   // x the view distance (m), y a plant's height (m)
    uvec4 counts; // x rings, y mesh (FAR_MESH_*), z plants the placement may write
    vec4 tips[FAR_TIP_TABLE]; // per wind speed: the tip's move along the wind (x) and up (y) per metre of height
};

layout(set = SET_PASS, binding = 0, std140) uniform FarParamsBlock { FarParams far; };

// A placed plant (std430, 32 bytes): its centre on the ground relative to O (xyz) and its
// rectangles' width (w); its identity's hash, its turn about the axis (radians, f32 bits) and
// its ring (λ, f32 bits).
struct FarPlant {
    vec4 centre_width;
    uvec4 hash_turn_ring;
};

// The finest lattice's point `id` (in ring 0's steps, world-anchored) as a hash.
uint far_hash(ivec2 id, uint salt) {
    uint h = uint(id.x) * 0x8da6b343u ^ uint(id.y) * 0xd8163841u ^ salt * 0x9e3779b9u;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    h *= 0x297a2d39u;
    return h ^ (h >> 15);
}

float far_unit(uint h) {
    return float(h >> 8u) / 16777216.0;
}

// The band's ramp at distance d from the band's eye: 0 where the blades are whole, 1 a leash short
// of the blade range and past it (the cull's, `far_band_ramp` of common/frame.glsl).
float far_band(float d) {
    return far_band_ramp(d, far.rings.z);
}

// The far field's end: whole to 90 % of the view distance, gone at it.
float far_end(float d) {
    return clamp((far.reach.x - d) / (0.1 * far.reach.x), 0.0, 1.0);
}

#endif
