// tests/draw_class.rs: beacons, a draw class with a candidate source of its own
// (`render::draw_class::CandidateSource`). A stored tile holds 2 + (first / 7) mod 6 beacons
// (its first blade's index), on a line across its cell half-way up its box; the tiles pass clamps them to the
// source's `most_per_slot` (5). Beacon r of a tile is kept when (first + r) mod 3 is not 0. The test's CPU
// reference applies the same rules.
#ifndef BEACONS_GLSL
#define BEACONS_GLSL

uint beacons_in(BladeTile tile) {
    return 2u + (tile.first / 7u) % 6u;
}

bool beacon_kept(BladeTile tile, uint rank) {
    return (tile.first + rank) % 3u != 0u;
}

// Beacon `rank` of ring slot `slot` on the ground plane: on a line across the slot's cell of the
// tile grid (`frame.cull_tiles`, `tile_grid`), found from the slot alone, as the beacons' pass
// finds it from a visible entry (`source_entry`).
vec2 beacon_xz(uint slot, uint rank) {
    vec2 cell = vec2(ivec2(frame.cull_tiles.zw) + ring_cell(slot));
    vec2 along = vec2((float(rank) + 0.5) / 8.0, 0.5);
    return vec2(frame_values.tile_grid.x) + (cell + along) * frame_values.tile_grid.y;
}

// Its height: half-way up the tile's box (the count pass hands it to the pass in the entry).
float beacon_y(BladeTile tile) {
    return 0.5 * (tile.min.y + tile.max.y);
}

#endif
