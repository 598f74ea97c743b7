#version 460
#extension GL_GOOGLE_include_directive : require
// tests/camera_grid.rs: a camera grid of ivec4 cells through `shaders/common/camera_grid.glsl`.
// `fill` writes each cell that entered with its world cell (xyz) and mark 0 (w); `mark` sets the
// mark of one world cell; `read` reads world cells back through the addressing readers use
// (local cell and the window's base).
#include "common/camera_grid.glsl"

layout(local_size_x = CAMERA_GRID_GROUP) in;

const uint MODE_FILL = 0u;
const uint MODE_MARK = 1u;
const uint MODE_READ = 2u;

layout(set = 0, binding = 0, std430) buffer Grid { ivec4 cells[]; };
layout(set = 0, binding = 1, std430) readonly buffer Control {
    ivec4 first; // the level's window's first world cell
    uvec4 mode;  // x MODE_*, y world cells in `at`, z a mark
    ivec4 at[];  // the world cells to mark or read
};
layout(set = 0, binding = 2, std430) writeonly buffer Read { ivec4 read[]; };
layout(push_constant) uniform Fill { CameraGridFill fill; };

uint level_slot(uvec3 local) {
    uvec3 dims = fill.dims.xyz;
    return fill.base.w * dims.x * dims.y * dims.z + camera_grid_slot(local, fill.base.xyz, dims);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (mode.x == MODE_FILL) {
        uvec3 local = camera_grid_entered(fill, i);
        cells[level_slot(local)] = ivec4(first.xyz + ivec3(local), 0);
    } else if (i < mode.y) {
        uvec3 local = uvec3(at[i].xyz - first.xyz);
        if (mode.x == MODE_MARK) {
            cells[level_slot(local)].w = int(mode.z);
        } else {
            read[i] = cells[level_slot(local)];
        }
    }
}
