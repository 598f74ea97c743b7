#version 460
#extension GL_GOOGLE_include_directive : require
// The press pass (issue #34, `render::animation::pressed`): every collider, and every `--cut`,
// sweeps its ground ellipse from where it was at the previous frame to where it is now; each cell
// of the pressed map it covers in that sweep takes the press (or the cut) at the last moment it
// was covered. One dispatch: each sweep's box of cells (within the window) one after another, an
// invocation per cell, which takes every sweep into account; a cell two boxes hold is processed by
// the invocation of the first box only, so no two invocations touch one cell. Dispatched in rows
// of at most 65 535 workgroups (`render::animation::pressed::PressPass`). A sweep over a whole interval makes the map the same at any frame rate: `--time T`
// presses the path from 0 to T in its first frame.
//
// A press bends the blades of a cell: along the motion on the collider's path, turning outwards
// towards the path's edge (outwards from a collider at rest), by an amount that is full within 30 % of the radius of the path and
// falls to 0 at its edge. A cell keeps the stronger of its current (recovering) bend and the new
// one. A collider presses only where its lowest point comes within PRESSED_REACH of the ground.
#define FRAME_FROM_STORAGE
#include "common/bindings.glsl"
#include "common/ground.glsl"
#include "animation/pressed.glsl"

layout(local_size_x = 64) in;

// The last moment of the sweep `k` covers `c` (x, z relative to O) as a share s of the frame's
// interval, and the distance of its closest approach over the radius; false if it misses.
bool swept(uint k, vec2 c, out float s_last, out float closest) {
    vec3 p0 = pressed_sweeps[3u * k].xyz;
    vec3 p1 = pressed_sweeps[3u * k + 1u].xyz;
    vec2 r = pressed_sweeps[3u * k + 2u].xz;
    vec2 q = (c - p0.xz) / r;
    vec2 d = (p1.xz - p0.xz) / r;
    float a = dot(d, d);
    float b = dot(q, d);
    float cq = dot(q, q) - 1.0;
    float s_near = a > 1e-12 ? clamp(b / a, 0.0, 1.0) : 0.0;
    closest = length(q - s_near * d);
    if (a <= 1e-12) {
        s_last = 1.0;
        return cq < 0.0;
    }
    float disc = b * b - a * cq;
    if (disc <= 0.0) {
        return false;
    }
    float root = sqrt(disc);
    float s1 = (b - root) / a;
    float s2 = (b + root) / a;
    s_last = min(s2, 1.0);
    return s2 >= 0.0 && s1 <= 1.0;
}

void main() {
    uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
    if (i >= pressed_counts.z) {
        return;
    }
    // The sweep whose box holds invocation i, and the cell.
    uint k = 0u;
    for (uint s = 1u; s < pressed_counts.x; s++) {
        k = uint(pressed_boxes[s].w) <= i ? s : k;
    }
    ivec4 box = pressed_boxes[k];
    uint j = i - uint(box.w);
    ivec2 w = box.xy + ivec2(j % uint(box.z), j / uint(box.z));
    // The first box that holds the cell processes it.
    for (uint s = 0u; s < k; s++) {
        ivec4 other = pressed_boxes[s];
        uint rows = (uint(s + 1u < pressed_counts.x ? pressed_boxes[s + 1u].w : int(pressed_counts.z)) - uint(other.w)) / uint(other.z);
        ivec2 local = w - other.xy;
        if (all(greaterThanEqual(local, ivec2(0))) && local.x < other.z && uint(local.y) < rows) {
            return;
        }
    }
    uint slot = pressed_slot(w);
    if (slot >= PRESSED_DIMS * PRESSED_DIMS) {
        return;
    }
    vec2 c = pressed_cell_centre(w);
    uint tag = pressed_tag(w);
    uvec4 cell = pressed_cells[slot];
    bool known = cell.w == tag;
    vec2 bend = known ? unpackHalf2x16(cell.x) : vec2(0.0);
    float pressed_t = known ? uintBitsToFloat(cell.y) : -1e30;
    float cut_t = known ? uintBitsToFloat(cell.z) : -1e30;
    bool changed = false;
    float ground = ground_height(c);
    float then = pressed_times.y;
    float span = pressed_times.x - pressed_times.y;
    for (uint k = 0u; k < pressed_counts.x; k++) {
        float s;
        float closest;
        if (!swept(k, c, s, closest)) {
            continue;
        }
        vec3 p0 = pressed_sweeps[3u * k].xyz;
        vec3 p1 = pressed_sweeps[3u * k + 1u].xyz;
        vec4 radii = pressed_sweeps[3u * k + 2u];
        if (mix(p0.y, p1.y, s) - radii.y > ground + PRESSED_REACH) {
            continue;
        }
        float t = then + s * span;
        if (radii.w > 0.5) {
            cut_t = max(cut_t, t);
            changed = true;
            continue;
        }
        // Along the motion on the path, turning outwards away from it towards its edge (a walked
        // trail: trodden forwards in the middle, parted at the sides); outwards from a collider at
        // rest.
        vec2 motion = p1.xz - p0.xz;
        float moving = dot(motion, motion);
        vec2 nearest = mix(p0.xz, p1.xz, moving > 1e-10 ? clamp(dot(c - p0.xz, motion) / moving, 0.0, 1.0) : 0.0);
        vec2 away = c - nearest;
        vec2 out_dir = dot(away, away) > 1e-10 ? normalize(away) : vec2(0.0);
        vec2 along = moving > 1e-10 ? motion * inversesqrt(moving) : vec2(0.0);
        vec2 lean = out_dir * closest + along * (1.0 - closest);
        vec2 dir = dot(lean, lean) > 1e-10 ? normalize(lean) : vec2(1.0, 0.0);
        vec2 press = dir * (1.0 - smoothstep(0.3, 1.0, closest));
        // The two presses compared at the later of their times, whichever sweep came first.
        float later = max(t, pressed_t);
        float left = length(bend) * pressed_recovery(later - pressed_t);
        if (length(press) * pressed_recovery(later - t) >= left && length(press) > 0.0) {
            bend = press;
            pressed_t = t;
            changed = true;
        }
    }
    if (changed) {
        pressed_cells[slot] = uvec4(packHalf2x16(bend), floatBitsToUint(pressed_t), floatBitsToUint(cut_t), tag);
    }
}
