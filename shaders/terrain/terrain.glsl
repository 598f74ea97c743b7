// A stored height grid's surface under a point: its height (the debug views' lines) and its normal
// under a blade root, for Belyaev's Fresnel term (lighting.glsl). Mirror
// `scene::terrain::Terrain::normal_at` on the CPU.
#ifndef MEADOW_TERRAIN_GLSL
#define MEADOW_TERRAIN_GLSL

// The cell of a stored height grid under world (x, z): the index of its first height in
// `heights[]` ((cells + 1)² floats, row by row, which the including shader declares), and where
// the point lies in it (`f`). `origin` is grid line 0's world x (= z), `step` the cell edge.
uint grid_terrain_cell(vec2 xz, float origin, float step, uint cells, out vec2 f) {
    vec2 g = clamp((xz - vec2(origin)) / step, vec2(0.0), vec2(float(cells)));
    uvec2 c = min(uvec2(floor(g)), uvec2(cells - 1u));
    f = g - vec2(c);
    return c.y * (cells + 1u) + c.x;
}

// Normal of a stored height grid at world (x, z): the gradient of the bilinear patch through the
// four heights of the cell the point lies in (continuous across cells, unlike a triangle's face
// normal).
vec3 grid_terrain_normal(vec2 xz, float origin, float step, uint cells) {
    vec2 f;
    uint i = grid_terrain_cell(xz, origin, step, cells, f);
    uint n = cells + 1u;
    float h00 = heights[i];
    float h10 = heights[i + 1u];
    float h01 = heights[i + n];
    float h11 = heights[i + n + 1u];
    float dx = mix(h10 - h00, h11 - h01, f.y);
    float dz = mix(h01 - h00, h11 - h10, f.x);
    return normalize(vec3(-dx, step, -dz));
}

// Height of a stored height grid at world (x, z), bilinear in the cell (the grid as above).
float grid_terrain_height(vec2 xz, float origin, float step, uint cells) {
    vec2 f;
    uint i = grid_terrain_cell(xz, origin, step, cells, f);
    uint n = cells + 1u;
    return mix(mix(heights[i], heights[i + 1u], f.x), mix(heights[i + n], heights[i + n + 1u], f.x), f.y);
}

#endif
