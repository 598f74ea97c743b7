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
#include "common/bindings.glsl"
#include "common/field.glsl"
#include "common/ground.glsl"
#include "far_field/far_field.glsl"

layout(local_size_x = 64) in;

layout(set = SET_PASS, binding = 1, std430) writeonly buffer FarPlants { FarPlant plants[]; };
// VkDrawIndexedIndirectCommand: index count, instance count (the kept plants), first index,
// vertex offset, first instance.
layout(set = SET_PASS, binding = 2, std430) buffer FarDraw { uint draw[5]; };

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

void main() {
    uint point = gl_GlobalInvocationID.x;
    uint per_ring = FAR_RING_SIDE * FAR_RING_SIDE;
    uint ring = point / per_ring;
    if (ring >= far.counts.x) {
        return;
    }
    uint at = point % per_ring;
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
        return; // past a bounded field's edge
    }
    vec2 offset = abs(p - eye);
    float cheb = max(offset.x, offset.y);
    if (cheb < start || cheb >= 2.0 * start) {
        return;
    }
    float lambda = log2(cheb / far.rings.x);
    bool next = ((lattice.x | lattice.y) & 1) == 0;
    if (!next && ring + 1u < far.counts.x) {
        float keep = clamp((float(ring + 1u) - lambda) / FAR_RING_FADE, 0.0, 1.0);
        if (far_unit(far_hash(id, 2u)) >= keep) {
            return;
        }
    }
    if (far_unit(far_hash(id, 3u)) >= ground_cover(p)) {
        return;
    }
    float width = FAR_WIDTH_STEPS * step0 * exp2(lambda);
    vec3 centre = vec3(p.x, ground_height(p), p.y);
    float radius = 0.5 * width + far.reach.y;
    float d = length(centre - frame_values.cull_eye.xyz);
    if (d - radius > far.reach.x || d + radius < far.rings.z) {
        return;
    }
    if (!sphere_in_view(centre + vec3(0.0, 0.5 * far.reach.y, 0.0), radius)) {
        return;
    }
    uint slot = atomicAdd(draw[1], 1u);
    if (slot >= far.counts.z) {
        return;
    }
    float turn = far_unit(far_hash(id, 4u)) * 2.0 * PI;
    plants[slot].centre_width = vec4(centre, width);
    plants[slot].hash_turn_ring = uvec4(h, floatBitsToUint(turn), floatBitsToUint(lambda), 0u);
}
