#version 460
#extension GL_GOOGLE_include_directive : require
// The far field's placement (`render::far_field::place_pass::FarPlacePass`): one invocation per lattice point
// of each ring (FAR_RING_SIDE² a ring). Ring r is the square annulus of Chebyshev distances
// [r0 2^r, r0 2^(r+1)) about the camera on the world lattice of step s0 2^r (whole blocks, so a
// point is O's cell plus integers): Zhang Xia's eq. 8–9, the plants per ring constant, their
// width 2^λ times ring 0's (λ = log2(d / r0), continuous, as eq. 8's length doubles per ring). A
// point the next ring's lattice does not hold fades out over the ring's outer half (a hashed
// threshold), so the next ring takes over the ones it holds unchanged. A plant is kept where the
// ground's cover keeps it (a hashed threshold under the cover: none where it is 0), in the
// culling camera's frustum and nearer than the view distance; kept plants are appended to
// `plants` and counted into the draw's instance count.
//
// Its variant `ordered` (`--fade blend`, Zhang Xia §5.4's pre-computed sorting): invocation o is
// the o-th point far to near, the outermost ring first and in each ring the pre-computed order of
// its lattice (`render::far_field::order`, the same for every ring: each ring's lattice holds the
// camera at the same place); every point writes its slot of `staged` (width 0: no plant), and
// far_order.comp compacts them in that order.
// variant ordered: FAR_ORDERED
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/ground.glsl"
#include "far_field/far_field.glsl"

layout(local_size_x = 64) in;

layout(set = SET_PASS, binding = 1, std430) writeonly buffer FarPlants { FarPlant plants[]; };
// VkDrawIndexedIndirectCommand: index count, instance count (the kept plants), first index,
// vertex offset, first instance.
layout(set = SET_PASS, binding = 2, std430) buffer FarDraw { uint draw[5]; };
#ifdef FAR_ORDERED
// The lattice's points far to near: order[rank] is the point's index in its ring's lattice.
layout(set = SET_PASS, binding = 3, std430) readonly buffer FarOrder { uint order[]; };
layout(set = SET_PASS, binding = 4, std430) writeonly buffer FarStaged { FarPlant staged[]; };
#endif

int floor_div(int a, int b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// Whether a sphere at `c` (relative to O) of radius `r` lies partly inside the culling camera's
// side planes (Gribb and Hartmann's planes of the matrix; reversed infinite Z: no far plane).
bool sphere_in_view(vec3 c, float r) {
    mat4 m = transpose(frame_values.cull_view_proj);
    vec4 planes[4] = vec4[4](m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1]);
    for (int i = 0; i < 4; i++) {
        vec4 p = planes[i];
        if (dot(p.xyz, c) + p.w < -r * length(p.xyz)) {
            return false;
        }
    }
    return true;
}

// The plant at point `at` of ring `ring`'s lattice, if one stands there and is seen.
bool place(uint ring, uint at, out FarPlant plant) {
    float start = far.rings.x * float(1u << ring);
    int blocks = int(far.rings.y / FAR_BLOCK + 0.5) << ring; // the ring's step in blocks
    vec2 eye = frame_values.cull_eye.xz;
    ivec2 origin = frame_values.field_cells.xy;
    // The ring's first lattice point: one to two steps outside its square's corner.
    ivec2 corner = origin + ivec2(floor((eye - vec2(2.0 * start)) / FAR_BLOCK));
    ivec2 lattice = ivec2(floor_div(corner.x, blocks), floor_div(corner.y, blocks)) - 1
        + ivec2(at % FAR_RING_SIDE, at / FAR_RING_SIDE);
    // The point in ring 0's steps: the plant's identity in every ring that holds it.
    ivec2 id = lattice << ring;
    uint h = far_hash(id, 0u);
    float step0 = far.rings.y;
    vec2 jitter = (vec2(far_unit(h), far_unit(far_hash(id, 1u))) - 0.5) * 0.5 * step0;
    vec2 p = vec2((lattice * blocks - origin) * int(FAR_BLOCK)) + jitter;
    if (!field_has_cell(origin + ivec2(floor(p / FAR_BLOCK)))) {
        return false; // past a bounded field's edge
    }
    vec2 offset = abs(p - eye);
    float cheb = max(offset.x, offset.y);
    if (cheb < start || cheb >= 2.0 * start) {
        return false;
    }
    float lambda = log2(cheb / far.rings.x);
    bool next = ((lattice.x | lattice.y) & 1) == 0;
    if (!next && ring + 1u < far.counts.x) {
        float keep = clamp((float(ring + 1u) - lambda) / FAR_RING_FADE, 0.0, 1.0);
        if (far_unit(far_hash(id, 2u)) >= keep) {
            return false;
        }
    }
    if (far_unit(far_hash(id, 3u)) >= ground_cover(p)) {
        return false;
    }
    // Half as long in the first rings (`render::far_field::NEAR_WIDTH`), whole from λ = 2.5.
    float near = mix(FAR_NEAR_WIDTH, 1.0, clamp(lambda - 1.5, 0.0, 1.0));
    float width = FAR_WIDTH_STEPS * step0 * exp2(lambda) * near;
    vec3 centre = vec3(p.x, ground_height(p), p.y);
    float radius = 0.5 * width + far.reach.y;
    float d = length(centre - frame_values.cull_eye.xyz);
    float from_band = length(centre - frame_values.band_eye.xyz);
    if (d - radius > far.reach.x || from_band + radius < far.rings.z) {
        return false;
    }
    if (!sphere_in_view(centre + vec3(0.0, 0.5 * far.reach.y, 0.0), radius)) {
        return false;
    }
    float turn = far_unit(far_hash(id, 4u)) * 2.0 * PI;
    plant.centre_width = vec4(centre, width);
    plant.hash_turn_ring = uvec4(h, floatBitsToUint(turn), floatBitsToUint(lambda), 0u);
    return true;
}

void main() {
    uint point = gl_GlobalInvocationID.x;
    uint per_ring = FAR_RING_SIDE * FAR_RING_SIDE;
    if (point >= far.counts.x * per_ring) {
        return;
    }
    FarPlant plant;
#ifdef FAR_ORDERED
    // The outermost ring first; the key (ring from the outside, rank) is kept with the plant.
    uint ring = far.counts.x - 1u - point / per_ring;
    uint rank = point % per_ring;
    if (!place(ring, order[rank], plant)) {
        plant = FarPlant(vec4(0.0), uvec4(0u));
    }
    plant.hash_turn_ring.w = point;
    staged[point] = plant;
#else
    if (!place(point / per_ring, point % per_ring, plant)) {
        return;
    }
    uint slot = atomicAdd(draw[1], 1u);
    if (slot < far.counts.z) {
        plants[slot] = plant;
    }
#endif
}
