// Camera-following grids on the GPU: the mirror of `render::camera_grid`. A level of `dims` cells
// per axis holds world cell w in slot w mod dims (toroidal), so a window that scrolls by whole
// cells keeps the cells that stay and writes only those that enter. Readers address a cell by
// its local index in the window and the window's base (the slot of its first cell); a fill
// shader takes `CameraGridFill` as its push constants and maps each invocation to a cell that
// entered (`camera_grid_entered`), dispatched over at least one (`render::camera_grid::record_fill`).
#ifndef MEADOW_CAMERA_GRID_GLSL
#define MEADOW_CAMERA_GRID_GLSL
#include "common/shared.glsl"

// The slot of local cell `local` (each axis below `dims`) of a window whose first cell sits at
// slot `base`: the wrap, then x fastest, then y, then z (`render::camera_grid::slot`).
uint camera_grid_slot(uvec3 local, uvec3 base, uvec3 dims) {
    uvec3 s = local + base;
    s -= mix(uvec3(0u), dims, greaterThanEqual(s, dims));
    return (s.z * dims.y + s.y) * dims.x + s.x;
}

// A fill dispatch's push constants (`render::camera_grid::FillPush`): the cells that entered, as
// boxes of local cells numbered one after another.
struct CameraGridFill {
    uvec4 box_start[CAMERA_GRID_BOXES]; // xyz the box's first local cell, w the cells of the boxes before it
    uvec4 box_size[CAMERA_GRID_BOXES];  // xyz its extent (0: an empty box)
    uvec4 base;                         // xyz the window's toroidal base, w the level
    uvec4 dims;                         // xyz cells per axis of a level, w the cells that entered
};

// The local cell invocation `i` fills. Invocations past the cells that entered fill the last one
// again (the same value written twice): nothing here branches on the push constants, since
// lavapipe before Mesa 23.1 compiles, and keeps, a shader variant per value of a uniform that
// decides control flow, and every scroll pushes other values.
uvec3 camera_grid_entered(CameraGridFill fill, uint i) {
    i = min(i, fill.dims.w - 1u);
    uint b = 0u;
    for (uint k = 1u; k < CAMERA_GRID_BOXES; k++) {
        b += i >= fill.box_start[k].w ? 1u : 0u;
    }
    uint j = i - fill.box_start[b].w;
    uvec3 size = max(fill.box_size[b].xyz, uvec3(1u));
    return fill.box_start[b].xyz + uvec3(j % size.x, (j / size.x) % size.y, j / (size.x * size.y));
}

#endif
