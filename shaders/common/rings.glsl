// The rings of cells around a centre cell, nearest first (`scene::tiles::ring_cell` on the CPU):
// slot 0 is the centre, ring r >= 1 holds slots (2r - 1)² .. (2r + 1)², walked along its four sides.
#ifndef MEADOW_RINGS_GLSL
#define MEADOW_RINGS_GLSL

ivec2 ring_cell(uint slot) {
    if (slot == 0u) {
        return ivec2(0);
    }
    int s = int(slot);
    int r = int(floor((sqrt(float(slot)) + 1.0) * 0.5));
    if ((2 * r - 1) * (2 * r - 1) > s) {
        r -= 1;
    }
    if ((2 * r + 1) * (2 * r + 1) <= s) {
        r += 1;
    }
    int p = s - (2 * r - 1) * (2 * r - 1);
    int side = p / (2 * r);
    int along = p % (2 * r);
    if (side == 0) {
        return ivec2(-r + along, -r);
    } else if (side == 1) {
        return ivec2(r, -r + along);
    } else if (side == 2) {
        return ivec2(r - along, r);
    }
    return ivec2(-r, r - along);
}

#endif
