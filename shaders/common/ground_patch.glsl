// One cell of the ground's grid from the heights at its four corners (h00, h10, h01, h11 in x, y,
// z, w) and where a point lies in it (`f`): the drawn surface's height and the normal the blades
// are lit with. Pure functions, shared by common/ground.glsl and the tests' probes.
#ifndef MEADOW_GROUND_PATCH_GLSL
#define MEADOW_GROUND_PATCH_GLSL

// Height of the drawn ground (flat between the vertices, split as terrain.vert splits a cell:
// (0,0)-(1,0)-(1,1) and (0,0)-(1,1)-(0,1)); `scene::terrain::Terrain::height_at` on the CPU.
float terrain_mesh_height(vec2 f, vec4 h) {
    return f.x >= f.y ? h.x + f.x * (h.y - h.x) + f.y * (h.w - h.y) : h.x + f.y * (h.z - h.x) + f.x * (h.w - h.z);
}

// The normal of the bilinear patch through the heights, for cells of `step` metres (continuous
// along each axis across the cell's edges, unlike a triangle's face normal): Belyaev §2.3's N_L
// under a blade's root. `scene::terrain::Terrain::normal_at` on the CPU.
vec3 bilinear_patch_normal(vec2 f, vec4 h, float step) {
    float dx = mix(h.y - h.x, h.w - h.z, f.y);
    float dz = mix(h.z - h.x, h.w - h.y, f.x);
    return normalize(vec3(-dx, step, -dz));
}

#endif
