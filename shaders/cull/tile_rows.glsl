// The blade class's per-tile rows (`render::draw_rows::TileRows`, TILE_ROWS_CAPACITY > 0): the
// scan (cull_scan.comp) writes, per LOD bucket, one VkDrawIndexedIndirectCommand per visible
// tile that draws blades of the bucket, in slot order (near to far), how many, and per draw a
// record: the first and end entries of the tile's blades in the visible list and the tile's
// ring slot. The blade pass draws each bucket's rows with
// one vkCmdDrawIndexedIndirectCount, and blade.vert's variant `tiles` finds its draw's record by
// gl_DrawID: the tile's id reaches the shader (Pelzer §7.4.2's one draw per cluster). Layout in
// words: MAX_LOD_BUCKETS draw counts, then per bucket TILE_ROWS_CAPACITY commands, then per
// bucket TILE_ROWS_CAPACITY records.
#ifndef MEADOW_TILE_ROWS_GLSL
#define MEADOW_TILE_ROWS_GLSL

uint tile_command_word(uint bucket, uint k) {
    return MAX_LOD_BUCKETS + (bucket * TILE_ROWS_CAPACITY + k) * DRAW_WORDS;
}

uint tile_record_word(uint bucket, uint k) {
    return MAX_LOD_BUCKETS + MAX_LOD_BUCKETS * TILE_ROWS_CAPACITY * DRAW_WORDS + (bucket * TILE_ROWS_CAPACITY + k) * TILE_RECORD_WORDS;
}

#endif
